# The format and stereo-view tests (tests/test_formats.cpp), as their own executable so that
# tests/CMakeLists.txt stays untouched. Included from tools/imageio/CMakeLists.txt when
# REPROJECT_BUILD_TESTS is on. The test also writes EXR files with the OpenEXR API directly (extra
# channels, Blender-style layer names, a tiled file), hence its own link to OpenEXR.
find_package(GTest REQUIRED)
include(GoogleTest)
# The top level adds this directory before its own enable_testing(); without this call ctest would
# not see the tests defined here.
enable_testing()

add_executable(reproject_format_tests ${PROJECT_SOURCE_DIR}/tests/test_formats.cpp)
target_link_libraries(reproject_format_tests PRIVATE reproject_imageio reproject OpenEXR::OpenEXR
  reproject_flags GTest::gtest GTest::gtest_main)
gtest_discover_tests(reproject_format_tests DISCOVERY_TIMEOUT 60)
