#!/usr/bin/env python3
"""Lists, for each C++ class, the .cpp files that define its members outside the class body, and
fails when one class's members are spread over more than a limit of files (default 3): the project's
rule that a class is read in at most three files (docs/architecture.md, Conventions).

Usage: class_files.py [--max-files N] [--all] [PATH...]
PATHs are files or folders (searched for .cpp/.cc, build*/ skipped); none: the library and the CLI
(every top-level folder but tests/, bench/, examples/, build*/). A member definition is a function
body at namespace scope whose name is qualified by a class, `Class::name(...) {` (templates' arguments
and enclosing namespaces dropped: `mapnav::Foo<T>::bar` counts for Foo); a qualifier made only of
namespaces (`detail::f`) is a free function. Nested classes count on their own (`Outer::Inner`).
Exits 1 when a class is over the limit, printing it and its files; --all lists every class with
members in more than one file.
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from funclen import sources, strip  # noqa: E402

NAMESPACE = re.compile(r'\bnamespace\s+([\w:]+)\s*\{')
# A qualified name just before its parameter list: A::B<T>::name( or A::operator==(.
QUALIFIED = re.compile(r'((?:\w+(?:<[^;{}()]*?>)?\s*::\s*)+)(~?\w+|operator\s*(?:\(\)|[^\s(]+))\s*\(')
TEMPLATE_ARGS = re.compile(r'<[^<>]*>')


def scopes_and_heads(text):
    """Yields (kind, head) for every brace block at namespace scope: kind 'ns' or 'other'."""
    depth_kinds = []  # per open brace: 'ns' or 'other'
    head_start = 0
    for i, c in enumerate(text):
        if c == ';':
            head_start = i + 1
        elif c == '{':
            head = text[head_start:i]
            at_ns = all(k == 'ns' for k in depth_kinds)
            is_ns = at_ns and (re.search(r'\bnamespace\b', head) or head.strip() in ('extern "C"', 'extern'))
            if at_ns and not is_ns:
                yield head, text.count('\n', 0, i) + 1
            depth_kinds.append('ns' if is_ns else 'other')
            head_start = i + 1
        elif c == '}':
            if depth_kinds:
                depth_kinds.pop()
            head_start = i + 1


def code(path):
    """The file's text, comments, literals and preprocessor lines blanked (newlines kept)."""
    text = strip(open(path, encoding='utf-8', errors='replace').read())
    return re.sub(r'(?m)^[ \t]*#.*(\\\n.*)*$', lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)


def namespace_names(texts):
    """Every name a `namespace X {` opens in the texts (std's too)."""
    names = {'std'}
    for text in texts:
        for m in NAMESPACE.finditer(text):
            names.update(m.group(1).split('::'))
    return names


def member_definitions(text, namespaces):
    """(class, member, line) for each member function defined at namespace scope in the text."""
    found = []
    for head, line in scopes_and_heads(text):
        if ')' not in head or re.search(r'=\s*$', head.strip()):
            continue
        h = re.sub(r'^\s*template\s*<[^{};]*?>\s*(?=[A-Za-z_])', '', head.strip())
        # The declarator's name: the last qualified name followed by '(' before the parameter list's
        # end; the return type's own qualified names (std::vector<int>) have no '(' after them.
        for m in QUALIFIED.finditer(h):
            qual = m.group(1)
            while TEMPLATE_ARGS.search(qual):
                qual = TEMPLATE_ARGS.sub('', qual)
            parts = [p.strip() for p in qual.split('::') if p.strip()]
            while parts and parts[0] in namespaces:
                parts.pop(0)
            if parts:
                found.append(('::'.join(parts), m.group(2), line))
            break
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--max-files', type=int, default=3)
    ap.add_argument('--all', action='store_true', help='list every class defined in more than one file')
    ap.add_argument('paths', nargs='*')
    a = ap.parse_args()
    if not a.paths:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        os.chdir(root)
        skip = ('.', 'build', 'out', 'runs', 'tests', 'bench', 'examples')
        a.paths = [d for d in sorted(os.listdir('.')) if os.path.isdir(d) and not d.startswith(skip)]
    texts = {path: code(path) for path in sources(a.paths)}
    namespaces = namespace_names(texts.values())
    files = {}  # (top-level folder, class) -> files: two modules may each have a class of one name
    for path, text in texts.items():
        if not path.endswith(('.cpp', '.cc')):
            continue
        module = os.path.normpath(path).split(os.sep)[0]
        for cls, _, _ in member_definitions(text, namespaces):
            files.setdefault((module, cls), set()).add(path)
    bad = 0
    for key in sorted(files, key=lambda k: (-len(files[k]), k)):
        cls, n = key[1], len(files[key])
        if n > a.max_files:
            print(f'{cls}: members defined in {n} files (> {a.max_files}): {" ".join(sorted(files[key]))}')
            bad += 1
        elif a.all and n > 1:
            print(f'{cls}: {n} files: {" ".join(sorted(files[key]))}')
    if not bad:
        print(f'class_files: no class with members defined in more than {a.max_files} files')
    sys.exit(1 if bad else 0)


if __name__ == '__main__':
    main()
