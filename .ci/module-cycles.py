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

PATH = re.compile(r"\b(crate|super|self)((?:::[A-Za-z_][A-Za-z0-9_]*)+|::\{)")
GROUP = re.compile(r"\b(crate|super|self)::((?:[A-Za-z_][A-Za-z0-9_]*::)*)\{([^}]*)\}", re.S)


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
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return "\n".join(line.split("//")[0] for line in text.splitlines())


def resolve(base, kind, parts, known):
    if kind == "crate":
        path = ()
    elif kind == "self":
        path = base
    else:  # super (possibly repeated)
        path = base[:-1]
        while parts and parts[0] == "super":
            path = path[:-1]
            parts = parts[1:]
    full = path + tuple(parts)
    # the longest prefix that is a module
    for n in range(len(full), -1, -1):
        if full[:n] in known:
            return full[:n]
    return path


def edges(mods):
    out = set()
    for mod, file in mods.items():
        with open(file, encoding="utf-8") as fh:
            text = strip_comments(fh.read())
        refs = []
        for m in PATH.finditer(text):
            parts = [p for p in m.group(2).split("::") if p and p != "{"]
            refs.append((m.group(1), parts))
        for m in GROUP.finditer(text):
            prefix = [p for p in m.group(2).split("::") if p]
            for item in m.group(3).split(","):
                item = item.strip().split(" as ")[0].strip()
                if item and item != "self":
                    refs.append((m.group(1), prefix + [p for p in item.split("::") if p and "{" not in p]))
        for kind, parts in refs:
            target = resolve(mod, kind, parts, mods)
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


def main():
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
