#!/usr/bin/env python3
"""Fails when a module imports a module that imports it back (issue 18).

For every crate of the workspace (a `src/` folder with `lib.rs` or
`main.rs`), each file is a module (`a.rs` and `a/mod.rs` are `a`,
`a/b.rs` is `a::b`). An edge a -> b is a path `crate::b...`, `super::...`
or `self::...` in a's file that names module b. Edges between a module and
its own ancestor or descendant are how Rust modules are built (a parent
declares and re-exports its children, a child uses its parent's items)
and are not counted; every other edge is lifted to the two siblings under
the modules' nearest common ancestor, and a cycle among siblings fails.

Usage: .ci/module-cycles.py [ROOT]   (default: the repository root)
"""
import os
import re
import sys

ROOTS = re.compile(r"\b(crate|super|self)\s*::")
PUB_USE = re.compile(r"\bpub(?:\s*\([^)]*\))?\s+use\s+")
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def modules(src):
    mods = {}
    for dirpath, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            rel = os.path.relpath(os.path.join(dirpath, f), src)[:-3].split(os.sep)
            if rel[-1] == "mod" or (len(rel) == 1 and rel[0] in ("lib", "main")):
                rel = rel[:-1]
            mods[tuple(rel)] = os.path.join(dirpath, f)
    return mods


def strip_comments(text):
    """The text without comments, string and char literals (a `//` or a
    path inside a string is not code)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
        elif c == "r" and re.match(r'r#*"', text[i:i + 130]) and not (i and (text[i - 1].isalnum() or text[i - 1] == "_")):
            hashes = re.match(r'r(#*)"', text[i:]).group(1)
            end = text.find('"' + hashes, i + len(hashes) + 2)
            out.append('""')
            i = n if end < 0 else end + 1 + len(hashes)
        elif c == '"':
            i += 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            out.append('""')
            i += 1
        elif c == "'" and re.match(r"'(\\.[^']*|[^\\'])'", text[i:i + 12]):
            m = re.match(r"'(\\.[^']*|[^\\'])'", text[i:i + 12])
            out.append("' '")
            i += len(m.group(0))
        else:
            out.append(c)
            i += 1
    return "".join(out)


def use_tree(text, i):
    """Parses a path or use tree at `text[i:]`: the list of segment lists
    it names (`a::{b, c::{d}}` gives [a, b], [a, c, d])."""
    def skip(i):
        while i < len(text) and text[i].isspace():
            i += 1
        return i

    def tree(i):
        i = skip(i)
        if text.startswith("{", i):
            paths, i = [], i + 1
            while True:
                i = skip(i)
                if text.startswith("}", i):
                    return paths, i + 1
                sub, i = tree(i)
                paths.extend(sub)
                i = skip(i)
                if text.startswith(",", i):
                    i += 1
                elif text.startswith("}", i):
                    return paths, i + 1
                else:
                    return paths, i
        if text.startswith("*", i):
            return [[]], i + 1
        m = IDENT.match(text, i)
        if not m:
            return [[]], i
        name, i = m.group(0), m.end()
        j = skip(i)
        if text.startswith("::", j):
            sub, i = tree(j + 2)
            return [[name] + p for p in sub], i
        alias = re.match(r"\s+as\s+([A-Za-z_][A-Za-z0-9_]*)", text[i:])
        if alias:
            i += alias.end()
        return [[name]], i

    return tree(i)[0]


def resolve(base, kind, parts, known, reexports=None):
    if kind == "crate":
        path = ()
    elif kind == "self":
        path = base
    else:  # super (possibly repeated)
        path = base[:-1]
        while parts and parts[0] == "super":
            path = path[:-1]
            parts = parts[1:]
    parts = [p for p in parts if p != "self"]
    full = path + tuple(parts)
    # the longest prefix that is a module
    for n in range(len(full), -1, -1):
        if full[:n] in known:
            # An item the module re-exports from another module counts as that one's.
            if reexports and n < len(full) and (full[:n], full[n]) in reexports:
                return reexports[(full[:n], full[n])]
            return full[:n]
    return path


def texts(mods):
    out = {}
    for mod, file in mods.items():
        with open(file, encoding="utf-8") as fh:
            out[mod] = strip_comments(fh.read())
    return out


def reexport_table(mods, text_of):
    """(module, item name) -> the module the item comes from, for every
    `pub use` (also `pub use child::Item` of a child module)."""
    table = {}
    for mod, text in text_of.items():
        for m in PUB_USE.finditer(text):
            for segs in use_tree(text, m.end()):
                if len(segs) < 2:
                    continue
                head, rest = segs[0], segs[1:]
                if head in ("crate", "super", "self"):
                    target = resolve(mod, head, rest[:-1], mods)
                elif mod + (head,) in mods:
                    target = resolve(mod, "self", segs[:-1], mods)
                else:
                    continue  # another crate
                if target != mod:
                    table[(mod, segs[-1])] = target
    return table


def edges(mods):
    out = set()
    text_of = texts(mods)
    reexports = reexport_table(mods, text_of)
    for mod, text in text_of.items():
        refs = []
        for m in ROOTS.finditer(text):
            for segs in use_tree(text, m.end()):
                refs.append((m.group(1), segs))
        for kind, parts in refs:
            target = resolve(mod, kind, parts, mods, reexports)
            if target != mod:
                out.add((mod, target))
    return out


def lift(a, b):
    n = 0
    while n < min(len(a), len(b)) and a[n] == b[n]:
        n += 1
    if n == len(a) or n == len(b):
        return None  # ancestor and descendant
    return a[: n + 1], b[: n + 1]


def cycles(graph):
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(comp)

    for v in list(graph):
        if v not in index:
            visit(v)
    return out


SELF_TEST = {
    # name: ({file: text}, has a cycle)
    "direct": ({"lib.rs": "mod a; mod b;", "a.rs": "use crate::b::X;", "b.rs": "use crate::a::Y;"}, True),
    "nested group": ({"lib.rs": "mod a; mod b; mod c;", "a.rs": "use crate::{c::{Z}, b::X};",
                      "b.rs": "use crate::a::Y;", "c.rs": ""}, True),
    "re-export": ({"lib.rs": "mod a; mod b; pub use b::Thing;", "a.rs": "use crate::Thing;",
                   "b.rs": "fn f() { crate::a::g() }"}, True),
    "string before use": ({"lib.rs": "mod a; mod b;", "a.rs": 'const U: &str = "http://x"; use crate::b::X;',
                           "b.rs": "use crate::a::Y;"}, True),
    "path in a string": ({"lib.rs": "mod a; mod b;", "a.rs": 'const U: &str = "crate::b::X";',
                          "b.rs": "use crate::a::Y;"}, False),
    "parent and child": ({"lib.rs": "mod a; use a::X;", "a.rs": "use crate::Y;"}, False),
}


def self_test():
    """Each blind spot a reviewer found is a case: the check must see it."""
    import tempfile
    for name, (files, cyclic) in SELF_TEST.items():
        with tempfile.TemporaryDirectory() as root:
            src = os.path.join(root, "src")
            os.makedirs(src)
            for f, text in files.items():
                with open(os.path.join(src, f), "w", encoding="utf-8") as fh:
                    fh.write(text)
            mods = modules(src)
            graph = {}
            for a, b in edges(mods):
                lifted = lift(a, b)
                if lifted:
                    graph.setdefault(lifted[0], set()).add(lifted[1])
            found = bool(cycles(graph))
            if found != cyclic:
                print(f"self-test {name!r}: cycle {'missed' if cyclic else 'reported wrongly'}")
                sys.exit(2)


def main():
    self_test()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    failed = False
    crates = 0
    for dirpath, dirs, files in os.walk(root):
        dirs[:] = [d for d in dirs if d not in ("target", ".git", "node_modules")]
        if os.path.basename(dirpath) != "src" or not ({"lib.rs", "main.rs"} & set(files)):
            continue
        crates += 1
        mods = modules(dirpath)
        graph = {}
        why = {}
        for a, b in edges(mods):
            lifted = lift(a, b)
            if lifted:
                graph.setdefault(lifted[0], set()).add(lifted[1])
                why.setdefault(lifted, []).append(("::".join(a), "::".join(b)))
        for comp in cycles(graph):
            failed = True
            names = sorted("::".join(c) for c in comp)
            print(f"{os.path.relpath(dirpath, root)}: modules import each other: {', '.join(names)}")
            members = set(comp)
            for (x, y), uses in sorted(why.items()):
                if x in members and y in members:
                    for a, b in sorted(set(uses))[:4]:
                        print(f"    {a} -> {b}")
    if failed:
        sys.exit(1)
    print(f"no module cycles ({crates} crates)")


if __name__ == "__main__":
    main()
