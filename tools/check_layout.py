#!/usr/bin/env python3
"""Checks the layout rules of docs/architecture.md on the source tree and exits 1 on a breach.

- engine/ (the runtime, its io/ and devices/) includes nothing from systems/ or tools/;
- systems/ and components/ include nothing from tools/;
- no source file is over 600 lines;
- no function in systems/ is over 80 lines (a definition at namespace or class scope, counted from
  the line of its opening brace to its closing one, lambdas included);
- no file cites a document outside the project (the project's own documents are in docs/);
- systems/kernels/ includes components/, other kernels and the engine utilities in KERNEL_ENGINE
  only: kernels take plain arrays and components, never the World or a system;
- no system includes another system's header: a unit of systems/ (a group folder, systems/solver,
  systems/surface, systems/cut, or a top-level system's .h/.cpp pair) includes its own headers, the
  kernels and the documented seams (SEAMS) only; the pipeline, the composition root, includes any.
  Any other include is an arrow back up, counted and printed; one is allowed only from ALLOWED,
  where its reason is written.

Usage: check_layout.py [ROOT]  (default: the repository holding this script)
"""
import os
import re
import sys

SOURCE_EXT = (".h", ".hpp", ".cpp", ".inl")
MAX_FILE_LINES = 600
MAX_FUNCTION_LINES = 80
# Documents that live outside the project; naming one sends a reader where they cannot follow.
OUTSIDE_DOCS = re.compile(r"\b(VERIFICATION\.md|DESIGN\.md|STYLE\.md|seed-paper\.txt)|\.\./shared/")
TEXT_EXT = SOURCE_EXT + (".md", ".py", ".sh", ".json", ".txt", ".cmake", ".in")
CONTROL = {"if", "for", "while", "switch", "catch", "do", "else", "try", "return"}
GROUPS = ("systems/solver/", "systems/surface/", "systems/cut/")
# The headers through which units of systems/ reach each other (docs/architecture.md).
SEAMS = {
    "systems/step_term.h": "the implicit step's terms: the ForceSystem's and the CollisionSystem's, walked by the solver",
    "systems/xfem_queries.h": "where the crack crosses an edge, a node's enriched displacement: read by the surface code",
}
# Engine headers a kernel may include: pure utilities that hold no World.
KERNEL_ENGINE = {
    "engine/parallel.h": "parallel_for and the fixed-order sums: results independent of the thread count",
    "engine/error.h": "InputError, for a tool mesh that cannot make a BVH",
    "engine/tet10_shapes.h": "the 10-node shape functions, pure functions of barycentric coordinates: the "
                             "output draws a cut quadratic element's pieces with them",
}
# Arrows back up inside systems/ that stay, each with its reason.
ALLOWED = {
    ("systems/cut/snap_cut_system.cpp", "systems/surface/mapping_system.h"):
        "the snapping baseline remeshes the tissue, so it rebuilds the surfaces as the boundary of its live "
        "pieces at the split (build_surface); deferring that would make the surface code know the snapping "
        "cutter's pieces instead",
}


def unit_of(rel):
    """The unit of systems/ a file belongs to: its group folder, or its own stem at the top level."""
    for g in GROUPS:
        if rel.startswith(g):
            return g
    return os.path.splitext(rel)[0]


def system_arrows(root):
    """(arrows, back_up, allowed_used, kernel_breaches) over the includes of systems/."""
    arrows, back_up, allowed, kernel = 0, [], [], []
    for path in source_files(root, "systems"):
        rel = os.path.relpath(path, root)
        for n, text in enumerate(open(path, encoding="utf-8"), 1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', text)
            if not m:
                continue
            inc = m.group(1)
            if rel.startswith("systems/kernels/"):
                if not (inc.startswith(("components/", "systems/kernels/")) or inc in KERNEL_ENGINE):
                    kernel.append(f"{rel}:{n}: a kernel includes {inc} (kernels include components and kernels)")
                continue
            if not inc.startswith("systems/") or inc.startswith("systems/kernels/"):
                continue
            arrows += 1
            if unit_of(inc) == unit_of(rel) or inc in SEAMS or rel.startswith("systems/pipeline."):
                continue
            if (rel, inc) in ALLOWED:
                allowed.append((rel, inc))
            else:
                back_up.append(f"{rel}:{n}: includes {inc}, another system's header (not a seam: {', '.join(SEAMS)})")
    return arrows, back_up, allowed, kernel


def source_files(root, folder):
    base = os.path.join(root, folder)
    for dirpath, _, names in os.walk(base):
        for name in sorted(names):
            if name.endswith(SOURCE_EXT):
                yield os.path.join(dirpath, name)


def strip_code(text):
    """The text with comments, strings and character literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == '"' and i > 0 and text[i - 1] == "R":  # raw string R"delim( ... )delim"
                k = text.find("(", i)
                delim = text[i + 1:k]
                j = text.find(")" + delim + '"', k)
                j = n if j < 0 else j + len(delim) + 2
            else:
                j = i + 1
                while j < n and text[j] != c:
                    j += 2 if text[j] == "\\" else 1
                j += 1
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    # Preprocessor lines (and their continuations) hold no braces of the code's structure.
    return re.sub(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", lambda m: re.sub(r"[^\n]", " ", m.group(0)), "".join(out),
                  flags=re.M)


def long_functions(path, limit):
    """(name, first line, lines) of each function definition longer than `limit` lines."""
    code = strip_code(open(path, encoding="utf-8").read())
    found, stack, head_start = [], [], 0  # stack: (kind, line of '{', name)
    line = 1
    for i, c in enumerate(code):
        if c == "\n":
            line += 1
        elif c in ";}{":
            if c == "{":
                head = code[head_start:i]
                enclosing_is_scope = all(k == "scope" for k, _, _ in stack)
                words = re.findall(r"[A-Za-z_]\w*", head)
                if re.search(r"\b(namespace|struct|class|union|enum)\b", head) and "(" not in head.split("{")[-1]:
                    kind = "scope"
                elif enclosing_is_scope and ")" in head and not (set(words[:1]) & CONTROL) and "=" not in head.split("(")[0]:
                    kind = "function"
                elif enclosing_is_scope and "(" not in head:
                    kind = "scope" if re.search(r"\bextern\b", head) else "block"
                else:
                    kind = "block"
                name = ""
                if kind == "function":
                    m = re.search(r"([~\w:]+)\s*\(", head)
                    name = m.group(1) if m else "?"
                stack.append((kind, line, name))
            elif c == "}" and stack:
                kind, start, name = stack.pop()
                if kind == "function" and line - start + 1 > limit:
                    found.append((name, start, line - start + 1))
            head_start = i + 1
    return found


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    breaches = []
    for folder in ("engine",):
        for path in source_files(root, folder):
            for n, text in enumerate(open(path, encoding="utf-8"), 1):
                if re.match(r'\s*#\s*include\s+"(systems|tools)/', text):
                    breaches.append(f"{os.path.relpath(path, root)}:{n}: the engine includes {text.strip()}")
    for folder in ("systems", "components"):
        for path in source_files(root, folder):
            for n, text in enumerate(open(path, encoding="utf-8"), 1):
                if re.match(r'\s*#\s*include\s+"tools/', text):
                    breaches.append(f"{os.path.relpath(path, root)}:{n}: {folder}/ includes {text.strip()}")
    for folder in ("engine", "systems", "components", "tools", "tests"):
        for path in source_files(root, folder):
            count = sum(1 for _ in open(path, encoding="utf-8"))
            if count > MAX_FILE_LINES:
                breaches.append(f"{os.path.relpath(path, root)}: {count} lines (at most {MAX_FILE_LINES})")
    for path in source_files(root, "systems"):
        for name, start, count in long_functions(path, MAX_FUNCTION_LINES):
            breaches.append(f"{os.path.relpath(path, root)}:{start}: function {name} is {count} lines "
                            f"(at most {MAX_FUNCTION_LINES} in systems/)")
    this = os.path.abspath(__file__)
    for dirpath, dirs, names in os.walk(root):
        dirs[:] = [d for d in dirs if not d.startswith((".", "build", "out")) and d != "corpus"]
        for name in names:
            path = os.path.join(dirpath, name)
            if not name.endswith(TEXT_EXT) and name not in ("CMakeLists.txt", "README.md") or path == this:
                continue
            for n, text in enumerate(open(path, encoding="utf-8", errors="replace"), 1):
                if OUTSIDE_DOCS.search(text):
                    breaches.append(f"{os.path.relpath(path, root)}:{n}: cites a document outside the project")
    arrows, back_up, allowed, kernel = system_arrows(root)
    breaches += back_up + kernel
    print(f"systems/ include arrows: {arrows} between headers of systems/; {len(back_up)} back up; "
          f"{len(allowed)} allowed with a reason")
    for rel, inc in allowed:
        print(f"  allowed: {rel} -> {inc}: {ALLOWED[(rel, inc)]}")
    for b in breaches:
        print(b)
    print(f"check_layout: {len(breaches)} breach{'es' if len(breaches) != 1 else ''}")
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
