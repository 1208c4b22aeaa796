#!/usr/bin/env python3
"""Holds the include graph to the arrows of docs/architecture.md.

Reads the table of modules in the architecture page (rows `| `NAME/` | `A`, `B` | ... |`: the module
and the modules it may include), then every C++ file of each module's folder (NAME/include and
NAME/src), and reports each `#include "mapnav/OTHER/..."` whose OTHER is not among the arrows, as
FILE:LINE: message. A module that is in the tree but not in the table, or the reverse, is an error
too, so that the page and the tree cannot drift apart. Exits 0 when every include follows an arrow,
1 otherwise (every violation listed), 2 on a usage error.

Usage: check_includes.py [--root DIR] [--doc FILE]
  --root  the source tree (default: this script's parent's parent)
  --doc   the architecture page (default: ROOT/docs/architecture.md)
"""
import argparse
import os
import re
import sys

ROW = re.compile(r'^\|\s*`([a-z_]+)/`\s*\|([^|]*)\|')
NAME = re.compile(r'`([a-z_]+)`')
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]mapnav/([a-z_]+)/')
SOURCES = ('.h', '.hpp', '.cpp', '.cc')


def arrows(doc):
    """module -> set of modules it may include, from the page's table."""
    table = {}
    with open(doc, encoding='utf-8') as f:
        for line in f:
            m = ROW.match(line)
            if m:
                table[m.group(1)] = set(NAME.findall(m.group(2)))
    return table


def modules(root):
    """The folders of the tree that are modules: their CMakeLists calls mapnav_module() or adds a
    library named mapnav_... (apps/: the CLI's library; python/: the Python module). tests/, bench/ and examples/ may include
    any module."""
    found = set()
    for name in sorted(os.listdir(root)):
        if name in ('tests', 'bench', 'examples'):
            continue
        cm = os.path.join(root, name, 'CMakeLists.txt')
        if os.path.isfile(cm) and re.search(r'^\s*(mapnav_module\(|add_library\(mapnav_|pybind11_add_module\(mapnav_)',
                                            open(cm, encoding='utf-8').read(), re.M):
            found.add(name)
    return found


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description='Holds the include graph to the arrows of docs/architecture.md.')
    ap.add_argument('--root', default=os.path.dirname(here))
    ap.add_argument('--doc')
    a = ap.parse_args()
    doc = a.doc or os.path.join(a.root, 'docs', 'architecture.md')
    if not os.path.isfile(doc):
        print(f'check_includes: {doc}: no such file', file=sys.stderr)
        return 2
    table = arrows(doc)
    if not table:
        print(f'{doc}: no module table (rows "| `NAME/` | `A`, `B` |")', file=sys.stderr)
        return 2
    problems = []
    tree = modules(a.root)
    for name in sorted(tree - table.keys()):
        problems.append(f'{doc}: module {name}/ is in the tree but not in the table')
    for name in sorted(table.keys() - tree):
        problems.append(f'{doc}: module {name}/ is in the table but not in the tree')
    for name in sorted(tree & table.keys()):
        allowed = table[name] | {name}
        for sub in ('include', 'src'):
            for dirpath, _, files in sorted(os.walk(os.path.join(a.root, name, sub))):
                for f in sorted(files):
                    if not f.endswith(SOURCES):
                        continue
                    path = os.path.join(dirpath, f)
                    with open(path, encoding='utf-8', errors='replace') as src:
                        for number, line in enumerate(src, 1):
                            m = INCLUDE.match(line)
                            if m and m.group(1) not in allowed:
                                rel = os.path.relpath(path, a.root)
                                may = ', '.join(sorted(table[name])) or 'no other module'
                                problems.append(f'{rel}:{number}: {name} includes mapnav/{m.group(1)}/, '
                                                f'but {name} may include only {may} ({os.path.relpath(doc, a.root)})')
    for p in problems:
        print(p)
    if problems:
        print(f'check_includes: {len(problems)} problem(s): the tree does not follow {os.path.relpath(doc, a.root)}')
        return 1
    print(f'check_includes: {len(tree)} modules, every include follows an arrow')
    return 0


if __name__ == '__main__':
    sys.exit(main())
