#!/usr/bin/env python3
"""The C++ sources' sizes against the layout's bounds (docs/design.md, "Layout").

Counts, outside tests/: each top-level folder's lines and its share of them all, every file over
MAX_FILE lines, and every function over MAX_FUNCTION lines (from the line of its opening brace's
declaration to its closing brace; a lambda counts within the function that holds it). Prints
them; exits 1 when a file or a function is over its bound or a folder over MAX_SHARE of the
lines, 0 otherwise.

usage: source_sizes.py [ROOT] [--table]   (--table: only the folders' lines, as a Markdown table)
"""
import re
import sys
from pathlib import Path

MAX_FILE = 600
MAX_FUNCTION = 120
MAX_SHARE = 0.20
SUFFIXES = {".h", ".cpp", ".inc"}
SKIP = {"tests", "build", ".git", "results", "docs", "scripts", "models", "cmake"}

STRIP = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)


def blank(match: re.Match) -> str:
    """a comment or a literal as spaces, its newlines kept (line numbers stay)"""
    return re.sub(r"[^\n]", " ", match.group(0))


def functions(text: str):
    """(name, first line, lines) of each function defined at namespace or class scope"""
    code = STRIP.sub(blank, text)
    stack = []  # per open brace: "scope" (namespace, class, enum, initializer) or "function"
    head_start = 0  # offset where the current declaration began
    line = 1
    found = []
    for i, c in enumerate(code):
        if c == "\n":
            line += 1
        elif c in ";":
            if not stack or stack[-1][0] == "scope":
                head_start = i + 1
        elif c == "{":
            if stack and stack[-1][0] in ("function", "inner"):
                stack.append(("inner", line, ""))
                continue
            head = code[head_start:i]
            words = head.strip()
            before_paren = words.split("(")[0]
            is_function = ("(" in words and ")" in words and "=" not in before_paren and
                           not re.search(r"\b(namespace|class|struct|union|enum)\b", before_paren))
            if is_function:
                name = re.findall(r"([A-Za-z_~][\w:~<>]*)\s*\(", words)
                stack.append(("function", words.count("\n") and
                              line - words.count("\n") or line, name[0] if name else "?"))
            else:
                stack.append(("scope", line, ""))
            head_start = i + 1
        elif c == "}":
            if not stack:
                continue
            kind, start, name = stack.pop()
            if kind == "function":
                found.append((name, start, line - start + 1))
            if not stack or stack[-1][0] == "scope":
                head_start = i + 1
    return found


def main() -> int:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    root = Path(args[0]) if args else Path(__file__).resolve().parent.parent
    files = sorted(p for p in root.rglob("*")
                   if p.suffix in SUFFIXES and p.is_file()
                   and not (set(p.relative_to(root).parts[:-1]) & SKIP)
                   and len(p.relative_to(root).parts) > 1)
    lines = {p: p.read_text(errors="replace").count("\n") for p in files}
    total = sum(lines.values())
    folders = {}
    for p, n in lines.items():
        top = p.relative_to(root).parts[0]
        folders[top] = folders.get(top, 0) + n
    if "--table" in sys.argv:
        print("| folder | lines | share |\n|---|---|---|")
        for top, n in sorted(folders.items(), key=lambda kv: -kv[1]):
            print(f"| {top}/ | {n:,} | {100 * n / total:.0f} % |")
        print(f"| all | {total:,} | |")
        return 0
    bad = 0
    for top, n in sorted(folders.items(), key=lambda kv: -kv[1]):
        over = n > MAX_SHARE * total
        bad += over
        print(f"{'OVER ' if over else ''}folder {top}/: {n} lines, {100 * n / total:.1f} %")
    for p, n in lines.items():
        if n > MAX_FILE:
            bad += 1
            print(f"OVER file {p.relative_to(root)}: {n} lines")
        for name, start, length in functions(p.read_text(errors="replace")):
            if length > MAX_FUNCTION:
                bad += 1
                print(f"OVER function {p.relative_to(root)}:{start} {name}: {length} lines")
    print(f"{total} lines in {len(files)} files; {bad} over their bounds")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
