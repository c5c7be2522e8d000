#!/usr/bin/env python3
"""Every path the docs name must exist in the repository.

Usage: check-doc-links.py [ROOT] [--code]

Scans docs/*.md and README.md (with --code also every tracked source file: C++, GLSL, Python,
shell, CMake) for path-like references -- `docs/...`, `common/...`, `cpu_ref/...`, `gpu/...`,
`compare/...`, `scripts/...`, `tests/...`, `scenes/...`, `app/...`, `frontend/...`,
`explore/...`, `examples/...`, `python/...`, any `NAME.md`, and the targets of Markdown links
`[text](target)` -- and exits 1 listing each one that names no file or folder of the repository, as FILE:LINE.

How a reference resolves:
- relative to the file that names it, then to the repository root (then, for a bare `NAME.md`,
  to docs/);
- `{a,b}` is expanded and `*` globbed (a pattern resolves when anything matches);
- a module named without its extension (`cpu_ref/masks`) resolves when a file of that stem
  exists (`cpu_ref/masks.cpp`, `.h`, `.frag`, ...);
- a Markdown link `FILE.md#anchor` to a file under docs/ or README.md also needs `anchor` to be
  one of that file's headings (GitHub's slugs);
- a section of the design, `docs/spec.md §N` or `spec.md §N.M` (in code also `SPEC §N`, the form
  the code cites it by), must be a numbered heading of docs/spec.md.
Generated paths (out/..., build/...) and anything outside the repository (URLs, absolute
paths, ../shared/...) are not checked; ALLOWED lists the few other names that are not files on
purpose.
"""
import glob
import os
import re
import subprocess
import sys
import unicodedata

# Paths a command writes, not files of the repository.
ALLOWED_PREFIXES = ("out/", "build/", "build-", "/")
# Docs a program writes from the code (a ctest keeps each current): their references are the
# code's, checked with --code.
GENERATED_DOCS = ("docs/shader-contract.md",)
# Names that look like paths but are not files of the repository on purpose.
ALLOWED = {
    "tests/tmp",  # MRR_TEST_TMP, made in the build tree
    "tests/fuzz/regressions/",  # made when the fuzzer first finds something (docs/hardening.md)
    # headers the build writes under build/generated/
    "compare/report_files.h", "explore/explore_files.h", "gpu/shader_sources.h", "common/cost_model_files.h",
}
# (file, reference) pairs that are not paths on purpose.
ALLOWED_IN = {
    ("tests/explore/test_explore_api.py", "../README.md"),  # a path-traversal request the server must refuse
}

# Upper-case names that are real files, not placeholders.
REAL_CAPS = {"README", "LICENSE", "CHANGELOG", "SPEC", "STYLE", "PLATFORM", "ANCHORS"}
ROOT_DIRS = ("docs", "common", "cpu_ref", "gpu", "compare", "scripts", "tests", "scenes", "app",
             "frontend", "explore", "examples", "python")
CODE_EXTENSIONS = (".cpp", ".h", ".inc", ".glsl", ".frag", ".vert", ".py", ".sh", ".cmake", ".js",
                   ".html", ".css", ".j2", ".txt")
PATH_CHARS = r"[A-Za-z0-9_.\-/*{},]"
# A path: one of the repository's top folders followed by a slash, or any NAME.md; not preceded
# by a character that would make it part of a longer path or word.
REF_RE = re.compile(r"(?<![A-Za-z0-9_./\-])((?:%s)/%s*|[A-Za-z0-9_.\-/{},*]*[A-Za-z0-9_\-}]\.md(?:#[A-Za-z0-9_\-%%.]*)?)"
                    % ("|".join(ROOT_DIRS), PATH_CHARS))
LINK_RE = re.compile(r"\]\(([^)\s]+)\)")
LINK_TEXT_RE = re.compile(r"!?\[[^\]]*\]\([^)\s]+\)")
VAR_RE = re.compile(r"\$\{[^}]*\}\S*|\$[A-Za-z_][A-Za-z0-9_]*\S*|\{[A-Za-z_][A-Za-z0-9_]*\}\S*")
SECTION_RE = re.compile(r"(?:spec\.md\)?|SPEC) ?§(\d+(?:\.\d+)?)")
URL_RE = re.compile(r"[a-z][a-z0-9+.\-]*://\S+")


def slug(heading):
    """GitHub's anchor for a Markdown heading."""
    text = re.sub(r"`", "", heading.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    out = []
    for ch in text:
        cat = unicodedata.category(ch)
        if ch in " -":
            out.append("-")
        elif ch == "_" or cat[0] in "LN" or cat == "Mn":
            out.append(ch)
    return "".join(out)


_anchor_cache = {}
_sections = None


def spec_sections(root):
    """The numbers of docs/spec.md's numbered headings: "12", "12.2", ..."""
    global _sections
    if _sections is None:
        _sections = set()
        with open(os.path.join(root, "docs", "spec.md"), encoding="utf-8") as f:
            for line in f:
                m = re.match(r"#{2,4} (\d+(?:\.\d+)?)\.? ", line)
                if m:
                    _sections.add(m.group(1))
    return _sections


def anchors(path):
    if path not in _anchor_cache:
        seen, found = {}, set()
        in_fence = False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.startswith("```"):
                    in_fence = not in_fence
                    continue
                m = None if in_fence else re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
                if m:
                    s = slug(m.group(1))
                    n = seen.get(s, 0)
                    seen[s] = n + 1
                    found.add(s if n == 0 else "%s-%d" % (s, n))
        _anchor_cache[path] = found
    return _anchor_cache[path]


def expand_braces(pattern):
    m = re.search(r"\{([^{}]*)\}", pattern)
    if not m:
        return [pattern]
    out = []
    for alt in m.group(1).split(","):
        out.extend(expand_braces(pattern[:m.start()] + alt + pattern[m.end():]))
    return out


def exists(root, base_dirs, ref):
    """Whether ref names something in the repository, looked up from each of base_dirs."""
    for candidate in expand_braces(ref):
        found = False
        for base in base_dirs:
            full = os.path.normpath(os.path.join(base, candidate))
            if not (full == root or full.startswith(root + os.sep)):
                continue  # outside the repository: not ours to check
            if "*" in full:
                if glob.glob(full):
                    found = True
            elif os.path.exists(full):
                found = True
            elif not os.path.splitext(full)[1] and glob.glob(glob.escape(full) + ".*"):
                found = True  # a module named by its stem
            if found:
                break
        if not found:
            return False
    return True


def clean(ref):
    ref = ref.rstrip(".,:;")
    while ref.endswith(")") and ref.count("(") < ref.count(")"):
        ref = ref[:-1]
    return ref.rstrip(".,:;")


def outside(root, file_dir, ref):
    full = os.path.normpath(os.path.join(file_dir, ref))
    return ref.startswith("../") and not full.startswith(root + os.sep)


def check_file(root, path, problems):
    rel = os.path.relpath(path, root)
    file_dir = os.path.dirname(path)
    is_md = path.endswith(".md")
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.readlines()
    except (UnicodeDecodeError, OSError):
        return
    for number, line in enumerate(lines, 1):
        text = URL_RE.sub(" ", line)
        # A path after a shell or CMake variable ($here/docs/x.md, ${CMAKE_SOURCE_DIR}/docs/x.md)
        # is made at run time: not checked.
        text = VAR_RE.sub("\0", text)
        refs = []
        if is_md:
            for m in LINK_RE.finditer(text):
                target = m.group(1)
                if re.match(r"[a-z][a-z0-9+.\-]*:", target):
                    continue  # mailto:, http:, ...
                refs.append(("link", target))
            text = LINK_TEXT_RE.sub(" ", text)  # a link's text names its target, checked above
        for m in SECTION_RE.finditer(text):
            if m.group(0).startswith("SPEC") and is_md:
                continue  # the docs name the file; `SPEC §N` there quotes the code's form
            if m.group(1) not in spec_sections(root):
                problems.append("%s:%d: %s (no such section in docs/spec.md)" % (rel, number, m.group(0)))
        refs.extend(("ref", m.group(1)) for m in REF_RE.finditer(text))
        for kind, raw in refs:
            ref, _, anchor = clean(raw).partition("#")
            if not ref:  # a link to an anchor of this file
                ref = os.path.basename(path) if kind == "link" else ""
                if not ref:
                    continue
            if ref in ALLOWED or (rel, ref) in ALLOWED_IN or ref.startswith(ALLOWED_PREFIXES) \
                    or outside(root, file_dir, ref) or "%" in ref:
                continue
            if not is_md and "/" not in ref and not re.fullmatch(r"[A-Z][A-Z_]*\.md", ref):
                continue  # in code a bare lower-case NAME.md is mostly a file it writes
            if not is_md and ref == "README.md":
                continue
            if "…" in ref or "..." in ref.replace("../", ""):
                continue
            bases = [file_dir, root]
            if ref.endswith(".md") and "/" not in ref:
                bases.append(os.path.join(root, "docs"))
            if not exists(root, bases, ref):
                if any(re.fullmatch(r"[A-Z][A-Z_]*", os.path.splitext(c)[0]) and c.split(".")[0] not in REAL_CAPS
                       for c in ref.split("/")):
                    continue  # a placeholder (cpu_ref/NAME.cpp, OUT_DIR/rule-sweep.md)
                problems.append("%s:%d: %s" % (rel, number, clean(raw)))
                continue
            if kind == "link" and anchor and ref.endswith(".md"):
                for base in bases:
                    target = os.path.normpath(os.path.join(base, ref))
                    if os.path.isfile(target):
                        break
                target_rel = os.path.relpath(target, root)
                if (target_rel == "README.md" or target_rel.startswith("docs" + os.sep)) \
                        and anchor not in anchors(target):
                    problems.append("%s:%d: %s (no heading with that anchor)" % (rel, number, clean(raw)))


def tracked_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], capture_output=True,
                             check=True).stdout.decode()
        return [os.path.join(root, p) for p in out.split("\0") if p]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for d, dirs, names in os.walk(root):
            dirs[:] = [x for x in dirs if not x.startswith(".") and x not in ("build", "out")]
            files.extend(os.path.join(d, n) for n in names)
        return files


def main(argv):
    code = "--code" in argv
    args = [a for a in argv if a != "--code"]
    if any(a.startswith("-") for a in args) or len(args) > 1:
        print(__doc__, file=sys.stderr)
        return 2
    root = os.path.realpath(args[0] if args else os.path.join(os.path.dirname(__file__), ".."))
    docs = sorted(glob.glob(os.path.join(root, "docs", "*.md"))) + [os.path.join(root, "README.md")]
    files = [p for p in docs if code or os.path.relpath(p, root) not in GENERATED_DOCS]
    if code:
        for p in tracked_files(root):
            name = os.path.basename(p)
            rel = os.path.relpath(p, root)
            if rel.startswith(("docs" + os.sep, "README.md")):
                continue
            if name.endswith(CODE_EXTENSIONS) or name == "CMakeLists.txt" or rel == os.path.join(".ci", "run"):
                files.append(p)
    problems = []
    for p in files:
        if os.path.isfile(p):
            check_file(root, p, problems)
    what = "docs/*.md, README.md" + (" and the tracked sources" if code else "")
    if problems:
        print("%d reference(s) in %s name no file of the repository:" % (len(problems), what))
        for p in problems:
            print("  " + p)
        return 1
    print("every path named in %s exists (%d files scanned)" % (what, len(files)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
