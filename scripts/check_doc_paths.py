#!/usr/bin/env python3
"""Checks that every repository path README.md and docs/*.md name exists.

    scripts/check_doc_paths.py [REPOSITORY]

A path is a word that starts with one of the repository's top-level folders (libstm/, docs/,
tests/, ...), in backticks or not: `libstm/mesh/load_mesh.h`, docs/BENCHMARKS.md,
libsdm/map/texel_targets. It exists when the file or folder does, or, for a name without an
extension (a module, as the docs often name one), when NAME.h, NAME.cpp, NAME.py or NAME.sh does.
Brace lists expand (`libsdm/{map,encode}`: both); a trailing :LINE is dropped. Words with
placeholders (NAME, *, <...>, ...) and paths outside the repository (../shared, build/, OUTDIR/)
are not checked. Prints every missing path with its file and line and exits 1 when there is one.
"""
import itertools
import os
import re
import sys

# The top-level folders whose paths the docs name (build/ and other outputs are not in the tree).
TOP = ("apps", "blender", "cmake", "docs", "examples", "libsdm", "libstm", "python", "scripts", "shaders", "tests")
PATH = re.compile(r"(?<![\w./~-])((?:%s)/[\w./{},+-]*)" % "|".join(TOP))
PLACEHOLDER = re.compile(r"[*<>]|\.\.\.|\bNAME\b|\bX\b")
EXTENSIONS = ("", ".h", ".cpp", ".py", ".sh")


def expand(word):
    """`a/{b,c}/d` -> [a/b/d, a/c/d]."""
    parts = re.split(r"\{([^{}]*)\}", word)
    choices = [[p] if i % 2 == 0 else p.split(",") for i, p in enumerate(parts)]
    return ["".join(c) for c in itertools.product(*choices)]


def exists(repo, path):
    full = os.path.join(repo, path)
    return any(os.path.exists(full + ext) for ext in EXTENSIONS)


def paths_in(line):
    for m in PATH.finditer(line):
        word = re.sub(r":\d+$", "", m.group(1))
        word = word.rstrip(".,:;")
        if PLACEHOLDER.search(word) or word.count("{") != word.count("}"):
            continue
        yield from expand(word)


def main():
    repo = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    docs = ["README.md"] + sorted(os.path.join("docs", f) for f in os.listdir(os.path.join(repo, "docs")) if f.endswith(".md"))
    missing = checked = 0
    for doc in docs:
        with open(os.path.join(repo, doc), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                for path in paths_in(line):
                    checked += 1
                    if not exists(repo, path.rstrip("/")):
                        missing += 1
                        print(f"{doc}:{number}: {path} does not exist in the repository; name the path as it now is "
                              f"(git log --follow -- {path} shows where it went), or drop it")
    print(f"check_doc_paths: {checked} paths named in {len(docs)} files, {missing} missing")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
