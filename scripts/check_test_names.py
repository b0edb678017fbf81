#!/usr/bin/env python3
"""Every Catch2 test name can be run by ctest: ctest hands the name to the test binary as its
first argument, so a name that starts with '-' would be read as an option and the test would
fail in no time without running. Usage: check_test_names.py TESTS_DIR"""
import pathlib
import re
import sys

bad = []
for path in sorted(pathlib.Path(sys.argv[1]).glob("*.cpp")):
    for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
        m = re.search(r'\b(?:TEST_CASE|SCENARIO)\s*\(\s*"(-[^"]*)"', line)
        if m:
            bad.append(f"{path}:{number}: test name starts with '-': \"{m.group(1)}\" (ctest passes it to Catch2 as an option; "
                       "start the name with a word, e.g. \"The --strict option ...\")")
print("\n".join(bad) if bad else "check_test_names: no test name starts with '-'")
sys.exit(1 if bad else 0)
