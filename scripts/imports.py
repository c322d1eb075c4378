#!/usr/bin/env python3
"""The import graph of src/ from its `crate::` paths: the circles between
modules and the arrows from the physics up to the layers above it.

Usage: python3 scripts/imports.py [--depth N]
A node is a module path cut to N components (default 2: `structure::beam`,
`scene::validate`, `simulation`); a parent and the children it uses are
arrows too, so a module with its children is often one circle by itself.
Old paths kept as shims in lib.rs are resolved first; unit tests (after
`#[cfg(test)]`) and `tests.rs` files are left out.
"""
import os
import re
import sys
from collections import defaultdict

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "src")
# The layers of the physics, lowest first; nothing in them may import the
# modules listed in ABOVE.
# The old (flat) names are listed too, to measure a commit before the layout.
PHYSICS = ["linalg", "structure", "vehicle", "contact", "system", "solver", "outputs",
           "band", "two_level", "complementarity", "beam", "bending", "mesh",
           "modal", "profile", "body", "force_element", "impact", "integrate",
           "iteration", "static_start", "output_mask"]
ABOVE = ["scene", "build", "assemble", "simulation", "design", "moving_load",
         "model", "fmi2", "fmu", "report", "study", "cli"]


def shims():
    """`pub use a::b as c;` and `pub use a::{b, c};` in lib.rs: old -> new."""
    text = open(os.path.join(SRC, "lib.rs")).read()
    found = {}
    for m in re.finditer(r"pub use ([\w:]+) as (\w+);", text):
        found[m.group(2)] = m.group(1)
    for m in re.finditer(r"pub use ([\w:]+)::\{([^}]*)\};", text):
        for name in m.group(2).replace("\n", " ").split(","):
            name = name.strip()
            if name:
                found[name] = m.group(1) + "::" + name
    for m in re.finditer(r"pub use ([\w:]+)::(\w+);", text):
        found[m.group(2)] = m.group(1) + "::" + m.group(2)
    return found


def module_of(path):
    rel = os.path.relpath(path, SRC)[:-3].split(os.sep)
    if rel[-1] in ("mod", "lib", "main"):
        rel = rel[:-1]
    return rel


def node(parts, depth):
    return "::".join(parts[:depth]) or "lib"


def modules():
    """Every module path that has a file."""
    found = set()
    for root, _, files in os.walk(SRC):
        for f in files:
            if f.endswith(".rs"):
                found.add("::".join(module_of(os.path.join(root, f))))
    return found


def longest_module(parts, known):
    for n in range(len(parts), 0, -1):
        if "::".join(parts[:n]) in known:
            return parts[:n]
    return parts[:1]


def edges(depth):
    alias = shims()
    known = modules()
    graph = defaultdict(set)
    for root, _, files in os.walk(SRC):
        for f in files:
            if not f.endswith(".rs") or f in ("lib.rs", "main.rs", "tests.rs"):
                continue
            path = os.path.join(root, f)
            here = node(module_of(path), depth)
            if here.startswith("cli"):
                continue
            # Unit tests (at a file's end by the project's convention) are not
            # part of the layering.
            text = open(path).read().split("#[cfg(test)]")[0]
            module = module_of(path)
            # A module's own children (`mod x;` then `x::...`) and its parent
            # (`super::`) are arrows too.
            for child in re.findall(r"^\s*(?:pub )?mod (\w+);", text, re.M):
                if re.search(r"\b" + child + r"::", text):
                    graph[here].add(node(module + [child], depth))
            if "super::" in text and len(module) > 1:
                graph[here].add(node(module[:-1], depth))
            for m in re.finditer(r"crate::((?:\w+::)*\w+)", text):
                parts = m.group(1).split("::")
                if parts[0] in alias:
                    parts = alias[parts[0]].split("::") + parts[1:]
                there = node(longest_module(parts, known), depth)
                if there != here:
                    graph[here].add(there)
    for source in graph:
        graph[source].discard(source)
    return graph


def circles(graph):
    """Strongly connected components with more than one node (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            scc = []
            while True:
                w = stack.pop()
                on.discard(w)
                scc.append(w)
                if w == v:
                    break
            if len(scc) > 1:
                out.append(sorted(scc))

    sys.setrecursionlimit(10000)
    for v in list(graph):
        if v not in index:
            visit(v)
    return out


def main():
    depth = int(sys.argv[sys.argv.index("--depth") + 1]) if "--depth" in sys.argv else 2
    graph = edges(depth)
    found = circles(graph)
    print(f"circles ({len(found)}):")
    for scc in found:
        print("  " + " <-> ".join(scc))
    up = sorted((a, b) for a, targets in graph.items() for b in targets
                if a.split("::")[0] in PHYSICS and b.split("::")[0] in ABOVE)
    print(f"arrows from the physics up ({len(up)}):")
    for a, b in up:
        print(f"  {a} -> {b}")


if __name__ == "__main__":
    main()
