#!/usr/bin/env python3
"""Include circles between units of the C++ sources (docs/design.md, "Layout").

A unit is a source's stem in its library: X.h (private, or public under include/puppet/<lib>/)
with X.cpp. An include of a header is an arrow from the including file's unit to the header's
unit. A circle is a strongly connected set of more than one unit, or a unit that includes itself
through another file of its own name elsewhere. Prints each circle and exits 1 when there is
one; exits 0 with "no include circles between N units" when there is none.

usage: include_circles.py [ROOT]   (ROOT: the project, default this script's parent's parent)
"""
import re
import sys
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SUFFIXES = {".h", ".cpp", ".inc"}


def unit_of(root: Path, path: Path) -> str:
    """'<library>:<folder under src or include/puppet/<library>>/<stem>'"""
    rel = path.relative_to(root)
    library = rel.parts[0]
    inner = rel.parts[1:]
    if inner[:1] == ("src",):
        inner = inner[1:]
    elif inner[:3] == ("include", "puppet", library):
        inner = inner[3:]
    return library + ":" + "/".join(inner[:-1] + (Path(inner[-1]).stem,))


def main() -> int:
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent
    # every top-level folder CMake builds, but the tests and the examples
    libraries = sorted(d.name for d in root.iterdir()
                       if (d / "CMakeLists.txt").is_file() and d.name not in ("tests", "examples"))
    files = [p for lib in libraries
             for p in (root / lib).rglob("*") if p.suffix in SUFFIXES and p.is_file()]
    by_path = {p.resolve(): p for p in files}
    public = {}  # "puppet/<lib>/<name>.h" -> file
    for p in files:
        rel = p.relative_to(root).parts
        if len(rel) > 3 and rel[1] == "include":
            public["/".join(rel[2:])] = p
    arrows = {}
    for p in files:
        here = unit_of(root, p)
        arrows.setdefault(here, set())
        for name in INCLUDE.findall(p.read_text(errors="replace")):
            target = public.get(name) or by_path.get((p.parent / name).resolve())
            if target is None:
                continue  # a system or third-party header
            there = unit_of(root, target)
            if there != here:
                arrows[here].add(there)
    # Tarjan's strongly connected components
    index, low, stack, on_stack, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(arrows.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in sorted(arrows):
        if v not in index:
            visit(v)
    for circle in circles:
        print("include circle: " + " -> ".join(circle))
    if circles:
        return 1
    print(f"no include circles between {len(arrows)} units")
    return 0


if __name__ == "__main__":
    sys.exit(main())
