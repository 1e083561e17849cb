#!/usr/bin/python3
"""Check (or fix) the C++ formatting of the files changed since the style was introduced.

Usage: tools/format_check.py [--since REV] [--fix] [--clang-format EXE] [FILE ...]

Every C++ file (.h, .cc) under include/, source/, tests/, tools/ and benchmarks/ that
differs from REV (default: the commit that added .clang-format), including uncommitted
and new files, must be exactly what clang-format makes of it with the repository's
.clang-format. Files nobody touched since then keep their old layout until they are
changed (a file only moved, same content, too): formatting a file is part of changing it. With FILE arguments only those files
are checked. --fix rewrites the files in place.

Exit codes: 0 all formatted, 1 some file is not (the first differences are printed),
2 bad usage, 77 skipped (no clang-format 14 -- other versions format differently --, or
not a git checkout; ctest reports the test as skipped, not passed).
"""
import argparse
import difflib
import pathlib
import re
import shutil
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
FOLDERS = ("include/", "source/", "tests/", "tools/", "benchmarks/")
VERSION = 14


def git(*args):
    return subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)


def find_clang_format(given):
    for name in ([given] if given else [f"clang-format-{VERSION}", "clang-format"]):
        exe = shutil.which(name)
        if exe:
            out = subprocess.run([exe, "--version"], capture_output=True, text=True).stdout
            m = re.search(r"version (\d+)", out)
            if m and int(m.group(1)) == VERSION:
                return exe
    return None


def changed_files(since):
    """C++ files that differ from `since` (committed, staged, modified or new), existing."""
    base = since
    if not base:
        r = git("log", "--diff-filter=A", "--format=%H", "--", ".clang-format")
        commits = r.stdout.split()
        base = commits[-1] if commits else "HEAD"  # not committed yet: the working tree's changes
    # a file only moved (a rename with the same content, R100) keeps its layout
    r = git("diff", "--name-status", "-M", base)
    if r.returncode != 0:
        return None, base
    names = set()
    for line in r.stdout.splitlines():
        fields = line.split("\t")
        if fields[0] != "R100":
            names.add(fields[-1])
    names |= set(git("ls-files", "--others", "--exclude-standard").stdout.split())
    files = [n for n in sorted(names)
             if n.startswith(FOLDERS) and n.endswith((".h", ".cc")) and (ROOT / n).is_file()]
    return files, base


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--since", help="git revision to compare with (default: the commit that added .clang-format)")
    ap.add_argument("--fix", action="store_true", help="rewrite the files in place")
    ap.add_argument("--clang-format", help="the clang-format executable (version 14)")
    ap.add_argument("files", nargs="*")
    a = ap.parse_args()
    exe = find_clang_format(a.clang_format)
    if not exe:
        print(f"format_check: SKIPPED, no clang-format {VERSION} found (apt-get install clang-format-{VERSION}; "
              "other versions format differently)")
        return 77
    if a.files:
        files, base = a.files, None
    else:
        if git("rev-parse", "--git-dir").returncode != 0:
            print("format_check: SKIPPED, not a git checkout (the changed files are not known)")
            return 77
        files, base = changed_files(a.since)
        if files is None:
            print(f"format_check: SKIPPED, revision {base} is not in this clone (a shallow clone?)")
            return 77
    bad = 0
    for f in files:
        path = ROOT / f if not pathlib.Path(f).is_absolute() else pathlib.Path(f)
        text = path.read_text()
        r = subprocess.run([exe, f"--style=file:{ROOT / '.clang-format'}", f"--assume-filename={path}"],
                           input=text, capture_output=True, text=True)
        if r.returncode != 0:
            print(f"{f}: clang-format failed: {r.stderr.strip()}")
            bad += 1
            continue
        if r.stdout == text:
            continue
        if a.fix:
            path.write_text(r.stdout)
            print(f"{f}: formatted")
            continue
        bad += 1
        diff = list(difflib.unified_diff(text.splitlines(), r.stdout.splitlines(), f, f + " (clang-format)",
                                         n=0, lineterm=""))
        print("\n".join(diff[:14]) + ("\n  ..." if len(diff) > 14 else ""))
    what = f"changed since {base[:12]}" if base else "given"
    print(f"format_check: {len(files)} C++ files {what}, {bad} not formatted"
          + (" (tools/format_check.py --fix formats them)" if bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
