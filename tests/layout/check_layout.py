#!/usr/bin/env python3
"""ctest Layout.Rules: the rules docs/ARCHITECTURE.md states about the tree, checked on every build.

* Includes point down: nothing under kernels/ includes src/ or tools/; nothing under src/ (its
  CMake files included) names tools/; the public headers include only the standard library and
  each other; the scenes (scene/) include only the public headers and their own; nothing under
  include/, src/ or kernels/ includes the scenes.
* src/ is the library alone: every C++ source under it is compiled into the target `reproject`
  (the top-level CMakeLists.txt's add_library(reproject ...)), and it has no subfolders.
* No hand-written C or C++ file under include/, src/, kernels/, scene/ or python/ (the Python
  package's binding) is longer than 400 lines.
* Every document a comment or a doc cites exists: a `NAME.md` is docs/NAME.md, a top-level file or
  a path that resolves; every `DESIGN §N` (or `DESIGN.md §N`) is a numbered section of docs/DESIGN.md.
"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
problems = []

def files(folder, suffixes):
    base = root / folder
    return sorted(p for p in base.rglob("*") if p.is_file() and p.suffix in suffixes) if base.exists() else []

SOURCES = {".cpp", ".hpp", ".h", ".c", ".py", ".pyi", ".in", ".cmake", ".txt", ".md"}
CODE = {".cpp", ".hpp", ".h", ".c"}

for p in files("kernels", CODE):
    for n, line in enumerate(p.read_text().splitlines(), 1):
        if re.match(r'\s*#\s*include\s+"(src|tools)/', line):
            problems.append(f"{p.relative_to(root)}:{n}: kernels/ includes from above: {line.strip()}")
for p in files("src", SOURCES):
    for n, line in enumerate(p.read_text().splitlines(), 1):
        if re.search(r'(^|[^\w.])tools/', line):
            problems.append(f"{p.relative_to(root)}:{n}: src/ names tools/: {line.strip()}")
for p in files("include", CODE):
    for n, line in enumerate(p.read_text().splitlines(), 1):
        m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
        if m and not m.group(1).startswith("reproject/"):
            problems.append(f"{p.relative_to(root)}:{n}: a public header includes {m.group(1)}")

scene_files = {p.name for p in files("scene", CODE)}
for p in files("scene", CODE):
    for n, line in enumerate(p.read_text().splitlines(), 1):
        m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
        if m and not m.group(1).startswith("reproject/") and m.group(1) not in scene_files:
            problems.append(f"{p.relative_to(root)}:{n}: the scenes include {m.group(1)} (only include/ and scene/)")
for folder in ("include", "src", "kernels"):
    for p in files(folder, CODE):
        for n, line in enumerate(p.read_text().splitlines(), 1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if m and (m.group(1).startswith("scene/") or m.group(1) in scene_files):
                problems.append(f"{p.relative_to(root)}:{n}: {folder}/ includes the scenes: {line.strip()}")

library = re.search(r"add_library\(reproject\s([^)]*)\)", (root / "CMakeLists.txt").read_text())
library_sources = set(library.group(1).split()) if library else set()
for p in files("src", {".cpp", ".c"}):
    if p.relative_to(root).as_posix() not in library_sources:
        problems.append(f"{p.relative_to(root)}: under src/ but not a source of the library (add_library(reproject ...))")
for p in sorted((root / "src").iterdir()) if (root / "src").is_dir() else []:
    if p.is_dir():
        problems.append(f"{p.relative_to(root)}/: a folder under src/, which holds the library alone")

for folder in ("include", "src", "kernels", "scene", "python"):
    for p in files(folder, CODE):
        count = len(p.read_text().splitlines())
        if count > 400:
            problems.append(f"{p.relative_to(root)}: {count} lines (at most 400)")

design = (root / "docs" / "DESIGN.md").read_text()
sections = set(re.findall(r"^##\s+(\d+)\.", design, re.M))
cited_files = set()
for folder in ("include", "src", "kernels", "scene", "python", "tests", "tools", "bench", "fuzz", "examples", "cmake",
               "docs", ".ci"):
    for p in files(folder, SOURCES | {""}):
        if "data" in p.parts or p.name == "check_layout.py":
            continue
        text = p.read_text(errors="replace")
        for n, line in enumerate(text.splitlines(), 1):
            for m in re.finditer(r"DESIGN(?:\.md)?\s+((?:§\d+(?:[–-]§?\d+)?(?:,\s*)?)+)", line):
                for number in re.findall(r"\d+", m.group(1)):
                    if number not in sections:
                        problems.append(f"{p.relative_to(root)}:{n}: DESIGN §{number} is not a section of docs/DESIGN.md")
            for m in re.finditer(r"(?<![\w/.-])([\w./-]*[A-Z][\w-]*\.md)\b", line):
                cited = m.group(1).lstrip("/")
                candidates = [p.parent / cited, root / cited, root / "docs" / pathlib.Path(cited).name]
                if not any(c.exists() for c in candidates):
                    problems.append(f"{p.relative_to(root)}:{n}: cites {cited}, which is not in the repository")

for problem in problems:
    print(problem)
print(f"layout: {len(problems)} problems")
sys.exit(1 if problems else 0)
