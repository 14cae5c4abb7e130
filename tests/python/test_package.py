# The package's face: one version number (CMakeLists.txt's, the same in the CLI and in the installed
# distribution's metadata; tests/c checks the C ABI's reproject_version()), stubs that name every
# public name with the runtime's parameters and defaults, option names that are the library's, and
# Python signatures for the calls. The stubs read are those of the package under test (the build
# tree's, or the installed one), next to its __init__.py.
import ast
import importlib.metadata
import inspect
import os
import pathlib
import pydoc
import re
import subprocess
import typing

import numpy as np
import pytest

import reproject
import reproject.metrics

ROOT = pathlib.Path(__file__).resolve().parents[2]
PACKAGE = pathlib.Path(reproject.__file__).resolve().parent
EMPTY = inspect.Parameter.empty


def cmake_version():
    match = re.search(r"project\(\s*reproject\s+VERSION\s+([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    assert match, "CMakeLists.txt: no project(reproject VERSION ...)"
    return match.group(1)


# ---- One version --------------------------------------------------------------------------------

def test_version_is_the_cmake_projects():
    assert re.fullmatch(r"\d+\.\d+\.\d+", reproject.__version__)
    assert reproject.__version__ == cmake_version()


def test_the_cli_prints_the_same_version(cli):
    completed = subprocess.run([cli, "--version"], capture_output=True, text=True)
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout == f"reproject {cmake_version()}\n"


def test_the_installed_distribution_has_the_same_version():
    # pip's metadata (pyproject.toml, with the version setup.py reads from CMakeLists.txt), when the
    # package under test is the one pip installed; the build tree has none. CI's run against the
    # installed package sets REPROJECT_EXPECT_INSTALLED=1, so there the metadata must be found.
    try:
        dist = importlib.metadata.distribution("reproject")
        installed = pathlib.Path(dist.locate_file("reproject/__init__.py")).resolve() == PACKAGE / "__init__.py"
    except importlib.metadata.PackageNotFoundError:
        dist, installed = None, False
    if os.environ.get("REPROJECT_EXPECT_INSTALLED") == "1":
        assert installed, f"{PACKAGE} has no pip metadata beside it"
    if not installed:
        pytest.skip("the package under test was not installed by pip")
    assert dist.version == cmake_version()
    assert dist.metadata["Name"] == "reproject"


# ---- Reading the stubs and the compiled signatures ----------------------------------------------

def literal(node):
    return EMPTY if node is None else ast.literal_eval(node)


def stub_parameters(function):
    """(name, kind, default) of a stub's def, in order."""
    a = function.args
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + a.defaults
    out = [(p.arg, inspect.Parameter.POSITIONAL_ONLY if p in a.posonlyargs else inspect.Parameter.POSITIONAL_OR_KEYWORD,
            literal(d)) for p, d in zip(positional, defaults)]
    if a.vararg:
        out.append((a.vararg.arg, inspect.Parameter.VAR_POSITIONAL, EMPTY))
    out += [(p.arg, inspect.Parameter.KEYWORD_ONLY, literal(d)) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    if a.kwarg:
        out.append((a.kwarg.arg, inspect.Parameter.VAR_KEYWORD, EMPTY))
    return out


def runtime_parameters(function):
    return [(p.name, p.kind, p.default) for p in inspect.signature(function).parameters.values()]


def split_top_level(text):
    """Splits at the commas outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, c in enumerate(text):
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        elif c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if text[start:].strip():
        parts.append(text[start:].strip())
    return parts


def compiled_parameters(function):
    """(name, kind, default) from the signature pybind11 writes on a compiled function's docstring's
    first line, "name(a: int, *, b: str = 'x') -> T", without a method's self."""
    line = function.__doc__.splitlines()[0]
    open_at = line.index("(")
    depth = 0
    for close_at in range(open_at, len(line)):
        depth += {"(": 1, ")": -1}.get(line[close_at], 0)
        if depth == 0:
            break
    out, kind = [], inspect.Parameter.POSITIONAL_OR_KEYWORD
    for part in split_top_level(line[open_at + 1:close_at]):
        if part == "*":
            kind = inspect.Parameter.KEYWORD_ONLY
            continue
        name, _, rest = part.partition(":")
        default = rest.partition(" = ")[2]
        out.append((name.strip(), kind, ast.literal_eval(default) if default else EMPTY))
    return out[1:] if out and out[0][0] == "self" else out


def public_stub_names(module):
    """name -> node for the stub's public names (a re-exported `import x as x` included)."""
    names = {}
    for node in module.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names[node.name] = node
        elif isinstance(node, ast.AnnAssign):
            names[node.target.id] = node
        elif isinstance(node, ast.ImportFrom):
            names.update({a.asname: node for a in node.names if a.asname == a.name})
    return {n: node for n, node in names.items() if not n.startswith("_") or n == "__version__"}


def decorators(node):
    return {d.id for d in node.decorator_list if isinstance(d, ast.Name)} | \
           {d.attr for d in node.decorator_list if isinstance(d, ast.Attribute)}


def literal_values(node):
    """The strings of a `Name: TypeAlias = Literal[...]`, or None for another annotation."""
    if isinstance(node.value, ast.Subscript) and getattr(node.value.value, "id", "") == "Literal":
        elements = node.value.slice.elts if isinstance(node.value.slice, ast.Tuple) else [node.value.slice]
        return tuple(e.value for e in elements)
    return None


def parse_stub(name):
    return ast.parse((PACKAGE / name).read_text())


# Attributes a class's instances get at run time (py::dynamic_attr), and a way to make one.
INSTANCES = {"ParallaxBudget": lambda: reproject.parallax_budget(np.ones((4, 6), np.float32), reproject.Decoder(),
                                                                 reproject.StereoCamera(0.03, 3.5))}


def check_class(cls, node):
    members = {}
    for item in node.body:
        if isinstance(item, ast.FunctionDef):
            members.setdefault(item.name, []).append(item)
        elif isinstance(item, ast.AnnAssign):
            members[item.target.id] = item
    runtime = {n for n in dir(cls) if not n.startswith("_")}
    stubbed = {n for n in members if not n.startswith("_")}
    instance_only = {n for n in stubbed - runtime if isinstance(members[n], ast.AnnAssign)}
    assert runtime == stubbed - instance_only, (cls.__name__, "runtime only:", runtime - stubbed,
                                                "stub only:", stubbed - runtime)
    if instance_only:
        instance = INSTANCES[cls.__name__]()
        assert all(hasattr(instance, n) for n in instance_only), (cls.__name__, instance_only)
    for name, member in members.items():
        static = inspect.getattr_static(cls, name, None)
        where = f"{cls.__name__}.{name}"
        if isinstance(member, ast.AnnAssign):  # a writable attribute (def_readwrite)
            assert name in instance_only or (isinstance(static, property) and static.fset is not None), where
            continue
        if "property" in decorators(member[0]):  # read-only
            assert isinstance(static, property) and static.fset is None, where
            continue
        assert static is not None, where
        is_static = "staticmethod" in decorators(member[0])
        assert isinstance(static, staticmethod) == is_static, where
        for overload in member:  # every overload has the compiled function's parameters
            stub = stub_parameters(overload)
            stub = stub if is_static else stub[1:]
            assert stub == compiled_parameters(getattr(cls, name)), where


def check_module(module, stub):
    names = public_stub_names(stub)
    runtime = {n for n in vars(module) if not n.startswith("_")} | {"__version__"} & set(vars(module))
    assert set(names) == runtime, ("runtime only:", runtime - set(names), "stub only:", set(names) - runtime)
    assert set(module.__all__) == runtime - {"__version__"}
    for name, node in names.items():
        value = getattr(module, name)
        if isinstance(node, ast.FunctionDef):
            assert runtime_parameters(value) == stub_parameters(node), name
        elif isinstance(node, ast.ClassDef):
            assert isinstance(value, type), name
            check_class(value, node)
        elif isinstance(node, ast.AnnAssign):
            values = literal_values(node)
            if values is not None:
                assert typing.get_args(value) == values, name
            elif isinstance(node.annotation, ast.Name):
                assert isinstance(value, {"str": str, "float": float, "int": int}[node.annotation.id]), name
            else:
                assert isinstance(value, tuple), name


# ---- The stubs name the package, parameter by parameter ------------------------------------------

def test_the_stub_names_every_public_name_with_its_parameters():
    assert (PACKAGE / "py.typed").is_file()
    check_module(reproject, parse_stub("__init__.pyi"))


def test_the_metrics_stub_too():
    check_module(reproject.metrics, parse_stub("metrics.pyi"))


def test_the_calls_have_the_compiled_functions_signatures():
    # The Python faces (python/reproject/*.py) and the functions they call: same parameters,
    # kinds and defaults, so a keyword added in C++ and not in Python (or the reverse) fails here.
    functions = [getattr(reproject, n) for n in reproject.__all__] + [reproject.metrics.psnr, reproject.metrics.ssim]
    faces = [f for f in functions if inspect.isfunction(f)]
    assert len(faces) == 14
    for face in faces:
        assert runtime_parameters(face) == compiled_parameters(face.__compiled__), face.__name__
        assert face.__doc__ and "documented there" not in face.__doc__, face.__name__
    text = pydoc.render_doc(reproject.warp, renderer=pydoc.plaintext)
    assert "warp(color, depth, *, color_space='linear'" in text and "hole_fill='background'" in text


def test_a_misspelt_keyword_is_still_explained_by_the_compiled_function():
    s = reproject.scene("pole", 32, 16)
    with pytest.raises(TypeError, match="did you mean 'hole_fill'"):
        reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, hole_fil="none")


# ---- The option names are the library's ----------------------------------------------------------

def listed(call):
    """The names an "unknown <what> '?' (a, b, c)" ValueError lists."""
    with pytest.raises(ValueError) as error:
        call()
    match = re.search(r"unknown \w+ '\?' \(([^)]*)\)", str(error.value))
    assert match, str(error.value)
    return tuple(match.group(1).split(", "))


def test_the_option_types_hold_the_librarys_names():
    s = reproject.scene("pole", 32, 16)
    camera = reproject.StereoCamera(0.03, 3.5)

    def warp(**options):
        return reproject.warp(s.color, s.depth, decoder=s.decoder, convergence=3.5, **options)

    args = typing.get_args
    assert args(reproject.Method) == reproject.methods == listed(lambda: warp(method="?"))
    assert args(reproject.Arch) == reproject.arches == listed(lambda: reproject.arch_supported("?"))
    assert args(reproject.HoleFill) == listed(lambda: warp(hole_fill="?"))
    assert args(reproject.EdgeMode) == listed(lambda: warp(edge="?"))
    assert args(reproject.Encoding) == listed(lambda: reproject.Decoder("?"))
    assert args(reproject.DepthFormat) == listed(lambda: warp(depth_format="?"))
    assert args(reproject.SceneName) == reproject.scenes == listed(lambda: reproject.scene("?"))
    assert args(reproject.ColorSpace) == listed(lambda: warp(color_space="?"))
    assert args(reproject.Eye) == listed(lambda: camera.projection_d3d(np.eye(4), "?"))
    # Directions: the library's names, and the underscore spellings it also takes.
    directions = listed(lambda: reproject.ParallaxModel.from_stereo(0.03, 3.5, 100, "?"))
    assert args(reproject.Direction) == directions + tuple(d.replace("-", "_") for d in directions)
    for direction in args(reproject.Direction):
        reproject.ParallaxModel.from_stereo(0.03, 3.5, 100, direction)
    # Pick sources are only returned: the four the library names (stereo.hpp), one of them here.
    model = camera.parallax(32, "left-to-right")
    assert reproject.pick(s.left_depth, s.right_depth, s.decoder, model, 16.0, 8).source in args(reproject.PickSource)
    assert set(args(reproject.PickSource)) == {"both", "left", "right", "none"}
