#!/usr/bin/env python3
"""No include cycle between the engine's files (docs/architecture.md, "Layers").

A file and its header are one node (engine/color/detector.h and .cpp); node A depends on node B
when a file of A includes B's header. Tests are left out (a test includes what it tests). Prints
every strongly connected component of more than one node and exits 1 when there is one.

    python3 tests/include_cycles.py engine"""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "engine"
include = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
edges = {}
for folder, _, files in os.walk(root):
    for name in files:
        if not name.endswith((".h", ".cpp")) or name.endswith("_test.cpp"):
            continue
        path = os.path.join(folder, name)
        node = os.path.relpath(os.path.splitext(path)[0], root)
        edges.setdefault(node, set())
        with open(path, encoding="utf-8") as f:
            for target in include.findall(f.read()):
                other = os.path.splitext(target)[0]
                if other != node and os.path.exists(os.path.join(root, target)):
                    edges[node].add(other)

# Tarjan's strongly connected components, iteratively.
index, low, on_stack, stack, components, counter = {}, {}, set(), [], [], [0]
for start in sorted(edges):
    if start in index:
        continue
    work = [(start, iter(sorted(edges.get(start, ()))))]
    index[start] = low[start] = counter[0]; counter[0] += 1
    stack.append(start); on_stack.add(start)
    while work:
        node, children = work[-1]
        advanced = False
        for child in children:
            if child not in index:
                index[child] = low[child] = counter[0]; counter[0] += 1
                stack.append(child); on_stack.add(child)
                work.append((child, iter(sorted(edges.get(child, ())))))
                advanced = True
                break
            if child in on_stack:
                low[node] = min(low[node], index[child])
        if advanced:
            continue
        work.pop()
        if work:
            low[work[-1][0]] = min(low[work[-1][0]], low[node])
        if low[node] == index[node]:
            component = []
            while True:
                n = stack.pop(); on_stack.discard(n); component.append(n)
                if n == node:
                    break
            if len(component) > 1:
                components.append(sorted(component))

for c in components:
    print("include cycle: " + " <-> ".join(c))
print(f"{len(edges)} files (header and source as one), {len(components)} include cycle(s)")
sys.exit(1 if components else 0)
