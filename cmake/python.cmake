# The Python package (python/: the extension module and python/reproject) and its tests
# (tests/python), against Debian's interpreter.
#
# The module is built for one interpreter: /usr/bin/python3 when it exists (Debian's, the one
# python3-numpy and python3-pytest install into), not whichever python3 is first on PATH (a pyenv
# or virtualenv one would find neither). -DPython3_EXECUTABLE=... picks another.
# Not when cross compiling: the module would be built for the target, and the host's interpreter
# (which runs its tests and finds its headers) cannot load it.
if(CMAKE_CROSSCOMPILING)
  message(STATUS "reproject Python module: not built when cross compiling (for ${CMAKE_SYSTEM_PROCESSOR}); "
                 "configure with -DREPROJECT_BUILD_PYTHON=OFF to say so")
  return()
endif()
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the module is built for")
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module)
if(Python3_FOUND)
  # pybind11 sees Python3_FOUND and uses that interpreter (its FindPython mode).
  find_package(pybind11 CONFIG QUIET)
endif()
set(_reproject_python_missing "")
if(NOT Python3_FOUND)
  set(_reproject_python_missing "Python 3 with its headers (Debian: python3-dev)")
elseif(NOT pybind11_FOUND)
  set(_reproject_python_missing "pybind11 (Debian: pybind11-dev)")
else()
  execute_process(COMMAND ${Python3_EXECUTABLE} -c "import numpy" RESULT_VARIABLE _reproject_no_numpy
                  OUTPUT_QUIET ERROR_QUIET)
  if(_reproject_no_numpy)
    set(_reproject_python_missing "NumPy for ${Python3_EXECUTABLE} (Debian: python3-numpy)")
  endif()
endif()

if(_reproject_python_missing AND REPROJECT_PYTHON_REQUIRED)
  # setup.py (pip) builds the package alone: without the module there is nothing to build.
  message(FATAL_ERROR "the Python package needs ${_reproject_python_missing}")
endif()
if(_reproject_python_missing)
  message(WARNING "REPROJECT_BUILD_PYTHON is ON but ${_reproject_python_missing} was not found: the Python "
                  "module and its tests are NOT built. Install it, or configure with -DREPROJECT_BUILD_PYTHON=OFF.")
  return()
endif()
message(STATUS "reproject Python package: for ${Python3_EXECUTABLE} (Python ${Python3_VERSION}), pybind11 ${pybind11_VERSION}")

# Where `cmake --install` puts the package (the directory reproject/): a directory the interpreter
# searches for this prefix.
# Debian's python3 reads <prefix>/local/lib/python3.X/dist-packages for its own /usr, i.e.
# /usr/local/lib/python3.X/dist-packages, which is lib/python3.X/dist-packages under the default
# prefix /usr/local; other Pythons use their site-packages (sysconfig's platlib), same relative path.
if(NOT DEFINED REPROJECT_PYTHON_INSTALL_DIR)
  execute_process(COMMAND ${Python3_EXECUTABLE} -c
    "import sys, sysconfig; p = sysconfig.get_path('platlib', vars={'base': '', 'platbase': ''}).lstrip('/'); print(p[len('local/'):] if p.startswith('local/') else p)"
    OUTPUT_VARIABLE _reproject_site OUTPUT_STRIP_TRAILING_WHITESPACE)
  set(REPROJECT_PYTHON_INSTALL_DIR ${_reproject_site} CACHE STRING
      "Where the Python package (the directory reproject/) is installed, relative to CMAKE_INSTALL_PREFIX")
endif()

# The module's CMake files go to python_module/, apart from python/ (the package itself, beside them).
add_subdirectory(${PROJECT_SOURCE_DIR}/python ${PROJECT_BINARY_DIR}/python_module)
if(REPROJECT_BUILD_TESTS)
  add_subdirectory(${PROJECT_SOURCE_DIR}/tests/python ${PROJECT_BINARY_DIR}/tests/python)
endif()
