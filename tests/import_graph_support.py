"""Import circles in a module graph, for the tests that check the layering.

A circle is a strongly connected group of more than one module: modules that import each
other, directly or through others. Tarjan's algorithm finds every such group in one pass
over the graph (R. Tarjan, "Depth-first search and linear graph algorithms", 1972).
"""

from __future__ import annotations


def strongly_connected_groups(edges: dict[str, set[str]]) -> list[list[str]]:
    """Every group of more than one module that import each other, directly or not (Tarjan,
    iterative so that a long chain of imports cannot exhaust the recursion limit)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    groups = []
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(sorted(edges[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            module, targets = work[-1]
            target = next(targets, None)
            if target is not None:
                if target not in index:
                    index[target] = low[target] = len(index)
                    stack.append(target)
                    on_stack.add(target)
                    work.append((target, iter(sorted(edges.get(target, ())))))
                elif target in on_stack:
                    low[module] = min(low[module], index[target])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[module])
            if low[module] == index[module]:
                group = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    group.append(member)
                    if member == module:
                        break
                if len(group) > 1:
                    groups.append(sorted(group))
    return groups
