#!/usr/bin/env python3
"""Checks the engine's layering (CI): no two engine modules include each other, directly or through others
(a module is NAME.h with NAME.cpp); the CPU-only modules reach no Vulkan header; the installed headers
(include/inkwell/) include nothing of the engine's; the apps include nothing of the engine's either, only the
public API (those files of theirs not yet moved onto it are listed, and the list may only shrink). Prints what it
finds and exits 1."""
import glob, os, re, sys

os.chdir(os.path.join(os.path.dirname(__file__), '..'))
files = glob.glob('engine/**/*.h', recursive=True) + glob.glob('engine/**/*.cpp', recursive=True)
module = lambda f: os.path.splitext(os.path.relpath(f, 'engine'))[0]
edges = {}
for f in files:
    for line in open(f, encoding='utf-8'):
        m = re.match(r'#include "([^"]+)"', line)
        if not m:
            continue
        for candidate in (os.path.join('engine', m.group(1)), os.path.join(os.path.dirname(f), m.group(1))):
            if os.path.exists(candidate):
                target = module(os.path.normpath(candidate))
                if target != module(f):
                    edges.setdefault(module(f), set()).add(target)
                break

cycles, done = set(), set()
def visit(node, path):  # depth first; an edge back into the path closes a cycle
    for target in sorted(edges.get(node, ())):
        if target in path:
            cycles.add(' -> '.join(path[path.index(target):] + [target]))
        elif target not in done:
            visit(target, path + [target])
    done.add(node)
for node in sorted(edges):
    if node not in done:
        visit(node, [node])

# CPU-only modules: the loaders, the fit, the plans and CPU references, exports. They must not reach Vulkan
# (the fuzz build and the ARM64 cross-build of these files need no Vulkan headers).
cpu_only = [m for m in edges.keys() | set(module(f) for f in files)
            if m.startswith('io/') or os.path.basename(m) in ('clean', 'hrbf', 'hrbf_io', 'model', 'refine_plan', 'refine_cpu',
                                            'select_plan', 'select_cpu', 'select_math', 'export', 'spacing',
                                            'image', 'files', 'common', 'points', 'shapes', 'compare', 'vector',
                                            'path_order', 'feature_lines', 'support')]
vulkan = {module(f) for f in files if '<vulkan/vulkan.h>' in open(f, encoding='utf-8').read()}
def reaches(node, seen):
    for target in edges.get(node, ()):
        if target not in seen:
            seen.add(target)
            reaches(target, seen)
    return seen
leaks = sorted(m for m in cpu_only if (reaches(m, {m}) & vulkan))

public = [f for f in glob.glob('include/inkwell/*.h')
          for line in open(f, encoding='utf-8')
          if re.match(r'#include "(?!inkwell/)', line)]
# The apps (the command line, the viewer) on the public API: an include of theirs that names a file of engine/ or
# spirv_shaders/ is a layering error (the build would refuse it too: the inkwell target does not see engine/).
APPS_ON_ENGINE = set()  # none left (issue 28); a file here would be one still to move
app_files = sorted(glob.glob('apps/**/*.h', recursive=True) + glob.glob('apps/**/*.cpp', recursive=True))
on_engine = set()
for f in app_files:
    for line in open(f, encoding='utf-8'):
        m = re.match(r'#include "([^"]+)"', line)
        if m and any(os.path.exists(os.path.join(root, m.group(1))) for root in ('engine', 'spirv_shaders')):
            on_engine.add(f)
apps_wrong = sorted(on_engine - APPS_ON_ENGINE)
apps_moved = sorted(APPS_ON_ENGINE - on_engine)

for c in sorted(cycles):
    print(f'check-layering: engine modules include each other: {c}')
for f in sorted(set(public)):
    print(f'check-layering: {f} includes a header outside include/inkwell/')
for m in leaks:
    print(f'check-layering: the CPU-only module {m} reaches a Vulkan header')
for f in apps_wrong:
    print(f'check-layering: {f} includes a header of engine/; the apps use the public API (include/inkwell/)')
for f in apps_moved:
    print(f'check-layering: {f} is on the public API now: take it off APPS_ON_ENGINE')
if cycles or public or leaks or apps_wrong or apps_moved:
    sys.exit(1)
print(f'check-layering: {len(edges)} engine modules, no include cycle, {len(cpu_only)} CPU-only ones without Vulkan; '
      f'the public headers stand alone; {len(app_files) - len(on_engine)} of the apps\' {len(app_files)} files on '
      'the public API alone')
