#!/usr/bin/env python3
"""check-docs.py [INKWELL]: keeps README.md and docs/ true to the tree and to the program (run by .ci/run).

Checks, for README.md and every docs/*.md:
  1. every file or folder named in `code` exists: a repository path (from the root or the page's folder), a
     file name found somewhere in the tree, or a path in the public test data the docs cite (assimp's models,
     CGAL's data); names of outputs and placeholders are listed in EXAMPLES below;
  2. every `inkwell COMMAND` names a command of the program, and every option written after `inkwell` in a
     command line, or alone in a code span (`--levels`), is one that some command's --help lists;
  3. every option that a command's --help lists is documented: in docs/usage.md, or for the commands that have
     a page of their own, on that page.
INKWELL defaults to build/inkwell (the README's test command builds it). Exit 1 with one line per finding."""
import glob
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
os.chdir(ROOT)
INK = sys.argv[1] if len(sys.argv) > 1 else "build/inkwell"

# Outputs the docs show a command writing, and placeholders: not files of the tree.
EXAMPLES = {"out.pdf", "B-diff.png", "dir/../x.obj", "frame_NNNN.png", "frame_0001.png", "manifest.json",
            "inkwell-drawing-N.png", "inkwell-view-N.png", "inkwell-view-N.svg", "armadillo.obj", "dragon.obj",
            "nefertiti.obj",
            # generated at configure time into the build tree and installed with the headers
            "include/inkwell/version.h",
            # the shared design notes beside the repository
            "ALGORITHM.md"}
# Options of the plotter tools (vpype, saxi) that docs/usage.md cites beside Inkwell's own.
FOREIGN = {"--layer", "--no-fit-page", "--minimum-path-length", "--sort-paths", "--path-join-radius",
           "--point-join-radius"}
# Where the public test data the docs cite lives once installed (scripts/install-deps.sh does not install it;
# a path under these is accepted when the data is absent).
DATA = ["/usr/share/assimp/models", "/usr/share/assimp/models-nonbsd"]
CGAL_DATA = "/usr/share/doc/libcgal-dev/data.tar.gz"
DATA_FILE = re.compile(r"\.(off|stl|obj|ply|glb|gltf|xyz|pwn)$")
DATA_PREFIXES = ("data/meshes/", "data/points_3/", "meshes/", "points_3/", "invalid/", "OFF/", "STL/", "OBJ/",
                 "PLY/", "glTF/", "glTF2/")
# Commands with a page of their own, where their options are documented.
PAGES = {"view": "docs/viewer.md", "capture": "docs/capture.md", "compare": "docs/capture.md",
         "bench": "docs/performance.md"}
FILEISH = re.compile(r"\.(md|cpp|h|hpp|glsl|comp|frag|vert|sh|py|json|cmake|txt|png|svg|pdf|obj|off|ply|stl|hrbf|"
                     r"glb|gltf|xyz|pts|xyzn)$")
OPTION = re.compile(r"(?<![\w-])(--[a-z][a-z0-9-]*)")

problems = []
files = subprocess.run(["git", "ls-files"], capture_output=True, text=True, check=True).stdout.split()
names = {os.path.basename(f) for f in files}
folders = set()
for f in files:
    d = os.path.dirname(f)
    while d:
        folders.add(d + "/")
        d = os.path.dirname(d)
folder_names = {os.path.basename(d.rstrip("/")) + "/" for d in folders}


def exists(page, name):
    if name in EXAMPLES or name in files or name in folders:
        return True
    if os.path.exists(os.path.join(os.path.dirname(page), name)):
        return True
    if "/" not in name.rstrip("/") and (name in names or name in folder_names):
        return True
    if any(f.endswith("/" + name) for f in files) or any(d.endswith("/" + name) for d in folders):
        return True
    if name.startswith(DATA_PREFIXES) or DATA_FILE.search(name):
        return in_test_data(name)
    return False


_data = None


def in_test_data(name):
    """A path or file name in the public test data (assimp-testmodels, libcgal-demo's data.tar.gz), accepted
    unchecked where neither is installed."""
    global _data
    if _data is None:
        _data = []
        for r in DATA:
            for d, _, fs in os.walk(r):
                _data += [os.path.relpath(os.path.join(d, f), r) for f in fs] + [os.path.relpath(d, r) + "/"]
        if os.path.exists(CGAL_DATA):
            r = subprocess.run(["tar", "tzf", CGAL_DATA], capture_output=True, text=True)
            _data += r.stdout.split()
    if not _data:
        return True
    return any(p == name or p.endswith("/" + name) for p in _data)


# The program's commands and options.
def run(*args):
    r = subprocess.run([INK, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"check-docs: {INK} {' '.join(args)} failed (exit {r.returncode}); build it first")
    return r.stdout


if not os.access(INK, os.X_OK):
    sys.exit(f"check-docs: {INK} not found; build it first (scripts/test.sh) or pass its path")
top = run("--help")
commands = re.findall(r"^  (\w+)\s{2,}", top.split("Subcommands:")[1], re.M)
helps = {c: run(c, "--help") for c in commands}
options = {c: set(OPTION.findall(h)) - {"--help"} for c, h in helps.items()}
# An option with a short form (-o,--output) is documented by either.
short = {c: dict((l, s) for s, l in re.findall(r"(?<![\w-])(-[a-zA-Z]),(--[a-z][a-z0-9-]*)", h))
         for c, h in helps.items()}
known = set().union(*options.values()) | set(OPTION.findall(top))

pages = ["README.md"] + sorted(glob.glob("docs/*.md"))
text = {p: open(p, encoding="utf-8").read() for p in pages}
for page in pages:
    body = text[page]
    for m in re.finditer(r"```[^\n]*\n(.*?)```|`([^`\n]+)`", body, re.S):
        span = m.group(1) if m.group(1) is not None else m.group(2)
        line_no = body.count("\n", 0, m.start()) + 1
        # 1. files and folders
        if m.group(2) is not None:
            name = span.strip().rstrip(".,:;")
            if " " not in name and re.fullmatch(r"[\w.\-/]+", name) and (FILEISH.search(name) or name.endswith("/")) \
                    and not name.startswith(("out/", "DIR/", "/tmp", "build", "/usr", ".")):
                if not exists(page, name):
                    problems.append(f"{page}:{line_no}: `{name}` does not exist")
            if re.fullmatch(r"--[a-z][a-z0-9-]*( [^`]*)?", span) and span.split()[0] not in known | FOREIGN:
                problems.append(f"{page}:{line_no}: option `{span.split()[0]}` is not an option of inkwell")
        # 2. command lines
        for cmd in re.finditer(r"(?:^|\$ |\(|`)[ \t]*(?:\S*/)?inkwell ([a-z][\w-]*)([^\n|;&]*)", span, re.M):
            word, rest = cmd.group(1), cmd.group(2)
            if word not in commands:
                problems.append(f"{page}:{line_no}: `inkwell {word}` is not a command")
                continue
            for opt in OPTION.findall(rest):
                if opt not in options[word] and opt not in known:
                    problems.append(f"{page}:{line_no}: `inkwell {word}` has no option {opt}")

# 3. every option of --help documented
for command, opts in options.items():
    where = [text["docs/usage.md"]] + ([text[PAGES[command]]] if command in PAGES else [])
    for opt in sorted(opts):
        forms = [opt] + ([short[command][opt]] if opt in short[command] else [])
        if not any(re.search(r"(?<![\w-])" + re.escape(f) + r"(?![\w-])", w) for f in forms for w in where):
            problems.append(f"inkwell {command} {opt}: not documented in docs/usage.md"
                            + (f" or {PAGES[command]}" if command in PAGES else ""))

for p in problems:
    print(p)
print(f"check-docs: {len(pages)} pages, {len(commands)} commands, {len(known)} options: "
      f"{len(problems)} problem(s)", file=sys.stderr)
sys.exit(1 if problems else 0)
