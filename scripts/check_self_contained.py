#!/usr/bin/env python3
"""Checks that every source file and every public header compiles on its own.

A unity build (CMAKE_UNITY_BUILD, what scripts/demo and scripts/test build) compiles 16 .cpp files
as one, so a file that uses a name without including its header still compiles there when an earlier
file of its batch included it, and breaks as soon as the batching changes or someone builds without
unity. This check reads the build's compile_commands.json and compiles, with each target's own
command but -fsyntax-only (parsed and type-checked, no code made):
  - every .cpp of every unity batch (the files CMake's Unity/unity_N_cxx.cxx include), alone, but
    each batch's first, which has nothing before it there and so was compiled alone by the build;
  - every public header (MODULE/include/mapnav/MODULE/*.h) that no checked .cpp includes first (a
    .cpp that includes its own header first checks it), alone, with the flags of a target of its
    module (a one-line file that includes it, so that #pragma once is not in the main file).
Files compiled outside the unity batches are compiled alone by the build already.

A file that compiled is remembered (an empty file in the cache folder, named by a hash of the
compiler, its flags and the file's preprocessed text, the source tree's path taken out): the next
check preprocesses it (about a tenth of the work) and compiles it again only when that text changed.
What failed is never remembered.

Reports every file that does not compile, with the compiler's first lines, then exits 1; exits 0 when
all compile, 2 on a usage error (no compile_commands.json, say).

Usage: check_self_contained.py [--root DIR] [--build DIR] [--jobs N] [--exclude PREFIX ...] [--cache DIR] [--list]
  --root     the source tree (default: this script's parent's parent)
  --build    the build folder (default: ROOT/build)
  --jobs     compilers run at the same time (default: the number of cores)
  --exclude  source-tree paths to leave out (default: tests/ bench/; give --exclude none for all)
  --cache    where to remember what compiled (default: $MAPNAV_CHECK_CACHE, else
             $XDG_CACHE_HOME/mapnav/self-contained, else ~/.cache/mapnav/self-contained; none: do not)
  --list     print the files that would be checked, and check nothing
"""
import argparse
import concurrent.futures
import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time

UNITY_INCLUDE = re.compile(r'^#include "([^"]+)"', re.M)
FIRST_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]')
PUBLIC_HEADER = re.compile(r'^([a-z_]+)/include/mapnav/\1/.+\.h$')


def syntax_only(arguments):
    """The compile command without its output, dependency file and input: -o X, -MD/-MF/-MT, -c F."""
    out, skip = [], False
    for a in arguments:
        if skip:
            skip = False
        elif a in ('-o', '-MF', '-MT', '-MQ', '-c'):
            skip = True
        elif a not in ('-MD', '-MMD'):
            out.append(a)
    return out + ['-fsyntax-only']


def first_include(path):
    """The name the file's first #include names ("mapnav/map/map.h"), or None."""
    with open(path, encoding='utf-8') as f:
        for line in f:
            m = FIRST_INCLUDE.match(line)
            if m:
                return m.group(1)
    return None


def jobs_from(build, root, exclude):
    """(what, command, folder, stdin) for every file to check, from the build's compile_commands.json.
    Paths under an exclude prefix (relative to root) are neither checked nor count as checking."""
    path = os.path.join(build, 'compile_commands.json')
    try:
        with open(path, encoding='utf-8') as f:
            entries = json.load(f)
    except (OSError, ValueError) as e:
        print(f'check_self_contained: {path}: {e} (configure the build first)', file=sys.stderr)
        sys.exit(2)
    kept = lambda rel: not any(rel.startswith(x) for x in exclude)
    sources, module_flags, first = [], {}, set()
    for e in entries:
        if '/Unity/unity_' not in e['file']:
            continue
        base = syntax_only(e['arguments'] if 'arguments' in e else shlex.split(e['command']))
        with open(e['file'], encoding='utf-8') as f:
            batch = [os.path.relpath(src, root) for src in UNITY_INCLUDE.findall(f.read())]
        for rel in filter(kept, batch):
            # A .cpp that includes its own header first checks that header too (the project's rule).
            first.add(first_include(os.path.join(root, rel)))
            module_flags.setdefault(rel.split('/')[0], (base, e['directory']))
            # The first file of a batch has nothing before it: the build compiled it alone already.
            if rel != batch[0]:
                sources.append((rel, base + [os.path.join(root, rel)], e['directory'], None))
    if not module_flags:
        return []
    widest = max(module_flags.values(), key=lambda f: sum(a.startswith('-I') for a in f[0]))
    headers = []
    for module in sorted(os.listdir(root)):
        include = os.path.join(root, module, 'include')
        for dirpath, _, files in os.walk(include):
            for name in sorted(files):
                rel = os.path.relpath(os.path.join(dirpath, name), root)
                m = PUBLIC_HEADER.match(rel)
                if m and kept(rel) and rel.split('/include/', 1)[1] not in first:
                    # A header-only module has no batch of its own: the target that sees most modules.
                    base, directory = module_flags.get(m.group(1)) or widest
                    headers.append((rel, base + ['-x', 'c++', '-'], directory, f'#include "{root}/{rel}"\n'))
    return sources + headers


def default_cache():
    if os.environ.get('MAPNAV_CHECK_CACHE'):
        return os.environ['MAPNAV_CHECK_CACHE']
    base = os.environ.get('XDG_CACHE_HOME') or os.path.join(os.path.expanduser('~'), '.cache')
    return os.path.join(base, 'mapnav', 'self-contained')


def cache_key(cmd, directory, stdin, root):
    """A hash of what decides whether the file compiles: the compiler (path, size, time), its
    arguments and the preprocessed text, with the source tree's path replaced so that a clone
    elsewhere finds the same key; None when the preprocessor fails (the compile then says why)."""
    preprocess = [a for a in cmd if a != '-fsyntax-only'] + ['-E']
    p = subprocess.run(preprocess, cwd=directory, input=stdin, capture_output=True, text=True)
    if p.returncode != 0:
        return None
    compiler = os.path.realpath(shutil.which(cmd[0]) or cmd[0])
    st = os.stat(compiler)
    h = hashlib.sha256(f'{compiler} {st.st_size} {st.st_mtime_ns}\0'.encode())
    for text in ('\0'.join(cmd), p.stdout):
        h.update(text.replace(root, '@ROOT@').encode())
        h.update(b'\0')
    return h.hexdigest()


def check(job, root, cache):
    """(what, exit code, compiler's messages, whether the cache said it compiles)."""
    rel, cmd, directory, stdin = job
    key = cache_key(cmd, directory, stdin, root) if cache else None
    if key and os.path.exists(os.path.join(cache, key)):
        return rel, 0, '', True
    p = subprocess.run(cmd, cwd=directory, input=stdin, capture_output=True, text=True)
    if p.returncode == 0 and key:
        try:
            os.makedirs(cache, exist_ok=True)
            open(os.path.join(cache, key), 'w').close()
        except OSError:
            pass  # a cache that cannot be written only costs time
    return rel, p.returncode, p.stderr, False


def main():
    ap = argparse.ArgumentParser(description='Checks that every source file and public header compiles on its own.')
    ap.add_argument('--root', default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument('--build')
    ap.add_argument('--jobs', type=int, default=os.cpu_count() or 1)
    ap.add_argument('--exclude', nargs='*', default=['tests/', 'bench/'])
    ap.add_argument('--cache', default=default_cache())
    ap.add_argument('--list', action='store_true')
    a = ap.parse_args()
    if a.jobs < 1:
        ap.error('--jobs must be at least 1')
    root = os.path.abspath(a.root)
    build = os.path.abspath(a.build or os.path.join(root, 'build'))
    exclude = [] if a.exclude == ['none'] else a.exclude
    cache = None if a.cache == 'none' else os.path.abspath(a.cache)
    jobs = jobs_from(build, root, exclude)
    if not jobs:
        print(f'check_self_contained: no unity-built file in {build}/compile_commands.json '
              '(is CMAKE_UNITY_BUILD on?)', file=sys.stderr)
        return 2
    if a.list:
        print('\n'.join(j[0] for j in jobs))
        return 0
    start = time.monotonic()
    failed, remembered = [], 0
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        for rel, rc, err, cached in pool.map(lambda j: check(j, root, cache), jobs):
            remembered += cached
            if rc != 0:
                failed.append(rel)
                lines = err.splitlines()
                print(f'{rel}: does not compile on its own:')
                print('\n'.join('    ' + l for l in lines[:12]))
                if len(lines) > 12:
                    print(f'    ... ({len(lines) - 12} more lines)')
    took = time.monotonic() - start
    sources = sum(1 for j in jobs if j[3] is None)
    print(f'check_self_contained: {sources} sources and {len(jobs) - sources} public headers, '
          f'{len(failed)} do not compile on their own ({took:.0f} s, {a.jobs} jobs, '
          f'{remembered} known from the cache{"" if cache else ", which is off"})')
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
