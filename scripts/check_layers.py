#!/usr/bin/env python3
"""Checks that the library folders include one another one way only (docs/DESIGN.md, section 2).

Each folder may include its own headers and those of the folders it lists below; an include of any
other project folder is reported with the file and line. Exit 1 when one is found.
usage: check_layers.py REPOSITORY_ROOT
"""
import os
import re
import sys

# folder -> the folders it may include (besides itself); order follows the layers.
ALLOWED = {
    'libstm/core': [],
    'libstm/geometry': ['libstm/core'],
    'libstm/mesh': ['libstm/core', 'libstm/geometry'],
    'libstm/skeleton': ['libstm/core', 'libstm/geometry', 'libstm/mesh'],
    'libstm/layout': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton'],
    'libstm/registration': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout'],
    'libstm/correspondence': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout',
                              'libstm/registration'],
    'libstm/render': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout'],
    'libstm/transfer': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout',
                        'libstm/registration', 'libstm/correspondence', 'libstm/render'],
    'libsdm/map': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout'],
    'libsdm/pose': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout'],
    'libsdm/decode': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout',
                      'libsdm/map', 'libsdm/pose'],
    'libsdm/encode': ['libstm/core', 'libstm/geometry', 'libstm/mesh', 'libstm/skeleton', 'libstm/layout',
                      'libsdm/map', 'libsdm/pose', 'libsdm/decode'],
}
INCLUDE = re.compile(r'^\s*#\s*include\s*"((?:libstm|libsdm)/[^/"]+)/[^"]+"')


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else '.'
    problems, checked = [], 0
    for folder, allowed in ALLOWED.items():
        path = os.path.join(root, folder)
        if not os.path.isdir(path):
            problems.append(f'{folder}: missing folder')
            continue
        for name in sorted(os.listdir(path)):
            if not name.endswith(('.h', '.cpp')):
                continue
            checked += 1
            with open(os.path.join(path, name), encoding='utf-8') as f:
                for no, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if m and m.group(1) != folder and m.group(1) not in allowed:
                        problems.append(f'{folder}/{name}:{no}: includes {m.group(1)}, a layer {folder} may not use')
    for folder in ('libstm', 'libsdm'):
        for name in os.listdir(os.path.join(root, folder)):
            if name.endswith(('.h', '.cpp')):
                problems.append(f'{folder}/{name}: a source outside every layer folder')
    for p in problems:
        print(p)
    print(f'{checked} files checked, {len(problems)} layering problem(s)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
