#!/usr/bin/python3
"""Largest source files and functions of granhydro's library and driver.

Usage: tools/code_size.py [N] [--limit-lines L] [--limit-function F] [--root DIR]

Prints the N (default 5) longest files and the N longest function bodies
under include/ and source/, and exits with 1 if any file is above L lines
(default 600) or any function above F lines (default 150).  A function is a
brace block opened after a parameter list at namespace or class level;
lambdas and local blocks count towards the function that holds them.  The
parser strips comments, string and character literals, so it needs no
compiler; it is a size gauge, not a C++ parser.
"""
import argparse
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
KEYWORDS = ("if", "for", "while", "switch", "catch", "do", "else", "return")


def strip(text):
    """Comments, strings and character literals blanked, newlines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = ")" + m.group(1) + '"'
            j = text.find(end, i) + len(end)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def drop_template_heads(head):
    """The text of a declaration head without its template<...> parameter lists."""
    out, i = [], 0
    while True:
        m = re.search(r"\btemplate\s*<", head[i:])
        if not m:
            out.append(head[i:])
            return "".join(out)
        out.append(head[i:i + m.start()])
        j, depth = i + m.end(), 1
        while j < len(head) and depth:
            depth += {"<": 1, ">": -1}.get(head[j], 0)
            j += 1
        i = j


def functions(path):
    text = strip(path.read_text())
    stack = []  # (kind, start line, name)
    head_start = 0
    line = 1
    found = []
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            head = "\n".join(l for l in text[head_start:i].splitlines() if not l.lstrip().startswith("#"))
            words = head.split()
            enclosing = stack[-1][0] if stack else "namespace"
            kind = "block"
            name = ""
            if enclosing in ("namespace", "class"):
                bare = drop_template_heads(head).strip()
                if re.match(r"(inline\s+)?namespace\b", bare) or bare.startswith('extern ""'):
                    kind = "namespace"
                elif re.match(r"(typedef\s+)?(class|struct|union|enum)\b", bare):
                    kind = "class"
                elif "(" in bare and not (words and words[0] in KEYWORDS) and not re.search(r"=\s*$", bare):
                    kind = "function"
                    m = re.findall(r"([A-Za-z_~][\w:~]*(?:<[\w\s,:]*>)?(?:::[\w~]+)*)\s*\(", bare)
                    name = m[0] if m else "?"
                    if name == "__attribute__" and len(m) > 1:
                        name = m[-1]
            stack.append((kind, line, name))
            head_start = i + 1
        elif c == "}":
            if stack:
                kind, start, name = stack.pop()
                if kind == "function":
                    found.append((line - start + 1, name, start))
            head_start = i + 1
        elif c == ";":
            head_start = i + 1
    return found


def main():
    global ROOT
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("count", nargs="?", type=int, default=5, metavar="N",
                   help="how many files and functions to list (default 5)")
    p.add_argument("--limit-lines", type=int, default=600, metavar="L", help="file limit (default 600)")
    p.add_argument("--limit-function", type=int, default=150, metavar="F", help="function limit (default 150)")
    p.add_argument("--root", default=None, metavar="DIR", help="the checkout (default: the one of this script)")
    a = p.parse_args()
    count, lim_file, lim_fun = a.count, a.limit_lines, a.limit_function
    if a.root is not None:
        ROOT = pathlib.Path(a.root).resolve()
    files = sorted(p for d in ("include", "source") for p in (ROOT / d).rglob("*")
                   if p.suffix in (".h", ".cc"))
    sizes = sorted(((len(p.read_text().splitlines()), p.relative_to(ROOT)) for p in files), reverse=True)
    funs = sorted(((n, name, p.relative_to(ROOT), s) for p in files for n, name, s in functions(p)),
                  reverse=True)
    print(f"longest files (limit {lim_file} lines):")
    for n, p in sizes[:count]:
        print(f"  {n:6d}  {p}")
    print(f"longest functions (limit {lim_fun} lines):")
    for n, name, p, s in funs[:count]:
        print(f"  {n:6d}  {name}  ({p}:{s})")
    bad = [s for s in sizes if s[0] > lim_file] + [f for f in funs if f[0] > lim_fun]
    print(f"{sum(1 for s in sizes if s[0] > lim_file)} files and "
          f"{sum(1 for f in funs if f[0] > lim_fun)} functions above the limits")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
