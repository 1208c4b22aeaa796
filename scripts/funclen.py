#!/usr/bin/env python3
"""Lists C++ functions longer than a limit (default 120 lines) and files longer than a limit
(default 700 lines): the project's size rule (docs/architecture.md, Conventions).

Usage: funclen.py [--max-function N] [--max-file N] [--top K] [PATH...]
PATHs are files or folders (searched for .cpp/.h/.hpp, build*/ skipped); none: the whole source
tree (every module, apps/, tests/, bench/, examples/). A function is a brace block opened after a
')' (and optional qualifiers) at namespace, class or file scope; lambdas and local classes count as
part of the function they sit in. Lines from the function's first line (the line holding its name)
to its closing brace. Exits 1 when anything is over a limit, listing each as FILE:LINE: message.
"""
import argparse
import os
import re
import sys


def strip(text):
    """Comments, string and char literals replaced by spaces (newlines kept)."""
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
            end = ')' + m.group(1) + '"'
            j = text.find(end, i)
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        elif c in '"\'':
            # a digit separator (1'000) is not a char literal
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(' ')
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == '\\' else 1
            j = min(n, j + 1)
            out.append(re.sub(r'[^\n]', ' ', text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return ''.join(out)


def functions(path):
    text = strip(open(path, encoding='utf-8', errors='replace').read())
    # Preprocessor lines out too.
    text = re.sub(r'(?m)^[ \t]*#.*(\\\n.*)*$', lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)
    stack = []  # (kind, start_line, name)
    header_start = 0  # offset where the text before the next '{' began
    found = []
    line = 1
    for i, c in enumerate(text):
        if c == '\n':
            line += 1
        elif c in ';':
            header_start = i + 1
        elif c == '{':
            head = text[header_start:i]
            parent = stack[-1][0] if stack else 'ns'
            kind = 'block'
            name = ''
            if parent in ('ns', 'class'):
                h = head.strip()
                # Attributes out: `struct [[gnu::visibility("hidden")]] X {` is a class, not a function.
                bare = re.sub(r'\[\[.*?\]\]', ' ', h, flags=re.S)
                if re.search(r'\bnamespace\b', h) or h.startswith('extern "C"') or h == 'extern':
                    kind = 'ns'
                elif re.search(r'\b(class|struct|union|enum)\b[^()]*$', bare) or re.search(r'\b(class|struct|union|enum)\b\s+\w+\s*(final\s*)?(:[^()]*)?$', bare):
                    kind = 'class'
                elif ')' in h and not re.search(r'=\s*$', h) and not h.endswith(','):
                    kind = 'func'
                    m = re.search(r'([~\w:<>]+)\s*\(', h)
                    name = m.group(1) if m else h[:40]
                    # first line of the function: the line holding its name
                    pos = header_start + len(text[header_start:i]) - len(text[header_start:i].lstrip())
                    first = text.count('\n', 0, pos) + 1
                    if m:
                        first = text.count('\n', 0, header_start + head.find(m.group(0))) + 1
                    stack.append(('func', first, name))
                    header_start = i + 1
                    continue
            stack.append((kind, line, name))
            header_start = i + 1
        elif c == '}':
            if stack:
                kind, start, name = stack.pop()
                if kind == 'func':
                    found.append((line - start + 1, start, name))
            header_start = i + 1
    return found


def sources(paths):
    for p in paths:
        if os.path.isfile(p):
            yield p
            continue
        for root, dirs, files in os.walk(p):
            dirs[:] = sorted(d for d in dirs if not d.startswith('build') and not d.startswith('.'))
            for f in sorted(files):
                if f.endswith(('.cpp', '.h', '.hpp', '.cc')):
                    yield os.path.join(root, f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--max-function', type=int, default=120)
    ap.add_argument('--max-file', type=int, default=700)
    ap.add_argument('--top', type=int, default=0, help='also list the K longest functions')
    ap.add_argument('paths', nargs='*')
    a = ap.parse_args()
    if not a.paths:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        os.chdir(root)
        a.paths = [d for d in sorted(os.listdir('.')) if os.path.isdir(d) and not d.startswith(('.', 'build', 'out', 'runs'))]
    bad = 0
    allf = []
    for path in sources(a.paths):
        n = sum(1 for _ in open(path, encoding='utf-8', errors='replace'))
        if n > a.max_file:
            print(f'{path}: file has {n} lines (> {a.max_file})')
            bad += 1
        for length, start, name in functions(path):
            allf.append((length, path, start, name))
            if length > a.max_function:
                print(f'{path}:{start}: {name}: {length} lines (> {a.max_function})')
                bad += 1
    if a.top:
        print(f'-- the {a.top} longest functions')
        for length, path, start, name in sorted(allf, reverse=True)[:a.top]:
            print(f'{length:5d} {path}:{start}: {name}')
    if not bad:
        print(f'funclen: no file over {a.max_file} lines, no function over {a.max_function}')
    sys.exit(1 if bad else 0)


if __name__ == '__main__':
    main()
