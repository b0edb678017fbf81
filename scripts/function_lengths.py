#!/usr/bin/env python3
"""Lists the longest functions of the C++ sources and fails when one is too long.

A function is a brace block that opens outside every other function (at file, namespace or class
level) after a header containing '('; its length counts the lines from the header's first line to
the closing brace, lambdas and local classes inside it included. Comments, strings and character
literals are skipped, so braces inside them do not count.

usage: function_lengths.py [--top N] [--max LINES] DIR...
exit 1 when a function is longer than --max (default 120), 0 otherwise.
"""
import argparse
import os
import re
import sys

CONTROL = re.compile(r'\b(if|for|while|switch|catch|do|else|try)\b\s*(\(|$)')


def strip_code(text):
    """Replaces comments and the insides of string and char literals by spaces (keeps newlines)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i))
            i = j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(')' + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c in '"\'':
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            out.append(c + ' ' * (j - i - 1) + (c if j < n else ''))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def functions(path):
    """Yields (length, first line, name) for each function defined in the file."""
    with open(path, encoding='utf-8', errors='replace') as f:
        code = strip_code(f.read())
    stack = []          # kinds of the open blocks: 'scope' or 'function' or 'block'
    header = ''         # text since the last ; { or } at a non-function level
    header_line = 1
    line = 1
    for c in code:
        if c == '\n':
            line += 1
        in_function = any(k[0] == 'function' for k in stack)
        if c == '{':
            if in_function:
                stack.append(('block',))
            else:
                h = header.strip()
                is_function = '(' in h and not CONTROL.search(h.split('(')[0]) \
                    and not h.startswith('namespace') and not re.search(r'=\s*$', h)
                if is_function:
                    name = re.findall(r'([~\w:]+)\s*\(', h)
                    stack.append(('function', header_line, name[0] if name else '?'))
                else:
                    stack.append(('scope',))
            header = ''
        elif c == '}':
            if stack:
                kind = stack.pop()
                if kind[0] == 'function':
                    yield line - kind[1] + 1, kind[1], kind[2]
            if not any(k[0] == 'function' for k in stack):
                header = ''
        elif c == ';' and not in_function:
            header = ''
        elif not in_function:
            if not header.strip() and not c.isspace():
                header_line = line
            header += c


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--top', type=int, default=10)
    ap.add_argument('--max', type=int, default=120)
    ap.add_argument('dirs', nargs='+')
    args = ap.parse_args()
    found = []
    for d in args.dirs:
        for root, _, files in os.walk(d):
            for name in files:
                if name.endswith(('.cpp', '.h', '.hpp', '.cc')):
                    p = os.path.join(root, name)
                    found += [(n, p, first, fn) for n, first, fn in functions(p)]
    found.sort(reverse=True)
    for n, p, first, fn in found[:args.top]:
        print(f'{n:5d}  {p}:{first}  {fn}')
    over = [f for f in found if f[0] > args.max]
    if over:
        print(f'{len(over)} function(s) longer than {args.max} lines', file=sys.stderr)
        return 1
    print(f'longest function: {found[0][0] if found else 0} lines (limit {args.max})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
