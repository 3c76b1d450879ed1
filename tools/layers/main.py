# SPDX-License-Identifier: GPL-3.0-or-later
"""The layer rule of src/, checked on the object files' symbols and the sources' includes.

src/layers.txt declares the order: one level per line, bottom first; the names on one line are
sibling layers, each a folder of src/. A file's layer is its first folder under src/. A file may
include and call files of its own layer and of lower levels only, and no two files may depend on
each other through any chain of calls and includes (a cycle), within one folder too.

The graph has one node per file: a header belongs to the .c file of the same name in the same
folder (arena.h to arena.c), a header without one (callback.h) is a node of its own. Its edges:
  - a call or any other reference: an object's undefined symbol (nm: U, w) that another object
    defines (T D B R C G S V W); static functions and data never leave their object, so they
    make no edge, and the include edges cover the header's static inline functions;
  - an include: #include "x.h" (or <x.h>) of a source or a header, resolved as the compiler
    does with src/ as an include directory: beside the including file first, then from src/.
    Preprocessor conditions are not evaluated: a guarded include counts.
Public headers (include/stabdae) are not files of src/: with --include DIR they are checked on
their own. Each says its layer in its first comment ("(layer: mbs)"): a layer of layers.txt, or
"umbrella" (above them all: it may include every layer's header) or "fmi" (above the umbrella).
A header may include the headers of its own layer and of lower levels only; one that includes
upward or sideways, or declares no layer, is a violation as a source's would be.

Usage: layers --src src --objects OBJ... [--include DIR] [--dot | --draw PNG | --picture PNG]
  OBJ: object files or directories searched for *.o (a ';'-separated list as one argument is
  split, as CMake's $<TARGET_OBJECTS:...> gives). An object belongs to the source whose path
  under src/ ends its own path once the .o is stripped (CMake's .../stabdae_obj.dir/core/lu.c.o
  is core/lu.c). A named object of no source is an error; one found in a directory is skipped
  with a note (a build directory keeps the objects of sources since moved).
Exit status: 0 clean (one summary line), 1 on any violation (one line each, then a summary),
2 on bad usage or a missing input.
--draw writes the graph's text (its levels, files and edges, one line each) into the PNG beside
the drawing; --picture reads it back and exits 1 when the picture shows another graph than the
code's (a file or an edge added, gone or changed in kind), naming what differs.
Standard library only; --draw imports matplotlib (use the harness's venv).
"""

import argparse
import collections
import os
import re
import struct
import subprocess
import sys
import zlib

SOURCE_SUFFIXES = ('.c', '.h')
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*(?:"([^"]+)"|<([^>]+)>)')
# nm's letters for a symbol an object defines for others (uppercase: global; V, W: weak;
# u: GNU unique; i: GNU indirect function) and for one it takes from another (w: weak)
DEFINED = set('TDBRCGSVWui')
UNDEFINED = set('Uw')


class Usage(Exception):
    """Bad usage or a missing input: exit status 2."""


# -- the declaration ---------------------------------------------------------------------------


class Layers:
    """src/layers.txt: levels bottom first, sibling layers on one line, and the files declared
    directly in src/ ("name.c: layer")."""

    def __init__(self, path):
        self.path = path
        self.levels = []  # [[layer, ...], ...], bottom first
        self.level_of = {}  # layer -> index in levels
        self.root_files = {}  # file directly in src/ -> layer
        try:
            with open(path, encoding='utf-8') as f:
                lines = f.readlines()
        except OSError as e:
            raise Usage(f'cannot read the layers declaration: {e}')
        pending_roots = []
        for number, line in enumerate(lines, 1):
            line = line.split('#', 1)[0].strip()
            if not line:
                continue
            where = f'{path}:{number}'
            if ':' in line:
                name, layer = (part.strip() for part in line.split(':', 1))
                if not name or '/' in name or not layer or ' ' in layer:
                    raise Usage(f'{where}: a file directly in src/ is declared as "name.c: layer"')
                pending_roots.append((where, name, layer))
                continue
            names = line.split()
            for name in names:
                if not re.fullmatch(r'[A-Za-z0-9_.-]+', name):
                    raise Usage(f'{where}: "{name}" is not a folder name')
                if name in self.level_of:
                    raise Usage(f'{where}: layer "{name}" declared twice')
                self.level_of[name] = len(self.levels)
            self.levels.append(names)
        if not self.levels:
            raise Usage(f'{path}: no level declared')
        for where, name, layer in pending_roots:
            if layer not in self.level_of:
                raise Usage(f'{where}: "{layer}" is not a declared layer')
            self.root_files[name] = layer

    def order(self):
        return ' < '.join('|'.join(names) for names in self.levels)


# -- the files and their graph -----------------------------------------------------------------


class Graph:
    def __init__(self, src, layers):
        self.src = src
        self.layers = layers
        self.files = []  # every .c and .h under src/, relative, '/'-separated
        self.node_of = {}  # file -> node (the .c a header belongs to, or itself)
        self.nodes = []  # node names, sorted
        self.layer_of = {}  # node -> layer (None: not in any declared layer)
        self.misplaced = []  # (kind, node, explanation)
        # (a, b) -> {'calls': {symbol}, 'includes': {written include}}
        self.edges = collections.defaultdict(lambda: {'calls': set(), 'includes': set()})

    def scan_sources(self):
        for dirpath, dirnames, filenames in os.walk(self.src):
            dirnames.sort()
            for name in sorted(filenames):
                if name.endswith(SOURCE_SUFFIXES):
                    rel = os.path.relpath(os.path.join(dirpath, name), self.src)
                    self.files.append(rel.replace(os.sep, '/'))
        if not self.files:
            raise Usage(f'no .c or .h file under {self.src}')
        present = set(self.files)
        for f in self.files:
            stem, ext = os.path.splitext(f)
            self.node_of[f] = stem + '.c' if ext == '.h' and stem + '.c' in present else f
        self.nodes = sorted(set(self.node_of.values()))
        for node in self.nodes:
            self.layer_of[node] = self._layer(node)

    def _layer(self, node):
        if '/' not in node:
            layer = self.layers.root_files.get(node)
            if layer is None:
                self.misplaced.append(
                    ('undeclared', node, 'directly in src/ and not declared in layers.txt')
                )
            return layer
        folder = node.split('/', 1)[0]
        if folder not in self.layers.level_of:
            self.misplaced.append(('unknown', node, f'folder {folder}/ is not a declared layer'))
            return None
        return folder

    def scan_includes(self):
        present = set(self.files)
        for f in self.files:
            with open(os.path.join(self.src, f), encoding='utf-8', errors='replace') as fh:
                for line in fh:
                    m = INCLUDE_RE.match(line)
                    if not m:
                        continue
                    written = m.group(1) or m.group(2)
                    target = self._resolve(
                        f, written, quoted=m.group(1) is not None, present=present
                    )
                    if target is None:
                        continue
                    a, b = self.node_of[f], self.node_of[target]
                    if a != b:
                        shown = f'"{written}"' if m.group(1) else f'<{written}>'
                        self.edges[(a, b)]['includes'].add(f'#include {shown}')

    @staticmethod
    def _resolve(including, written, quoted, present):
        candidates = []
        if quoted:
            candidates.append(os.path.join(os.path.dirname(including), written))
        candidates.append(written)
        for c in candidates:
            c = os.path.normpath(c).replace(os.sep, '/')
            if c in present:
                return c
        return None

    def scan_objects(self, objects, nm):
        sources = [f for f in self.files if f.endswith('.c')]
        defined = collections.defaultdict(set)  # symbol -> {node}
        undefined = {}  # node -> {symbol}
        seen = {}
        for obj, named in objects:
            node = self._source_of_object(obj, sources)
            if node is None:
                if named:
                    raise Usage(f'the object {obj} belongs to no .c file under {self.src}')
                # a directory may keep the objects of sources since moved or removed
                print(
                    f'layers: note: {obj} belongs to no .c file under {self.src}: skipped',
                    file=sys.stderr,
                )
                continue
            if node in seen:
                raise Usage(f'two objects for {node}: {seen[node]} and {obj}')
            seen[node] = obj
            refs = undefined.setdefault(node, set())
            for name, kind in read_symbols(nm, obj):
                if kind in UNDEFINED:
                    refs.add(name)
                elif kind in DEFINED:
                    defined[name].add(node)
        for node, refs in undefined.items():
            for name in refs:
                for target in defined.get(name, ()):
                    if target != node:
                        self.edges[(node, target)]['calls'].add(name)
        return [s for s in sources if s not in seen]

    def _source_of_object(self, obj, sources):
        stem = obj.replace(os.sep, '/')
        for suffix in ('.o', '.obj'):
            if stem.endswith(suffix):
                stem = stem[: -len(suffix)]
                break
        best = None
        for s in sources:
            if (stem == s or stem.endswith('/' + s)) and (best is None or len(s) > len(best)):
                best = s
        return best

    def level(self, node):
        layer = self.layer_of.get(node)
        return None if layer is None else self.layers.level_of[layer]

    # -- the rule ------------------------------------------------------------------------------

    def layer_violations(self):
        """[(kind, a, b)] for the edges that go up or sideways."""
        out = []
        for a, b in sorted(self.edges):
            la, lb = self.level(a), self.level(b)
            if la is None or lb is None:
                continue
            if lb > la:
                out.append(('up', a, b))
            elif lb == la and self.layer_of[a] != self.layer_of[b]:
                out.append(('sideways', a, b))
        return out

    def components(self, edges):
        """The strongly connected components of more than one node of the graph of these edges
        (Tarjan, iterative), each sorted, in the order of their first node."""
        succ = collections.defaultdict(list)
        for a, b in sorted(edges):
            succ[a].append(b)
        index, low, on_stack, stack, out = {}, {}, set(), [], []
        counter = 0
        for root in self.nodes:
            if root in index:
                continue
            work = [(root, iter(succ[root]))]
            index[root] = low[root] = counter
            counter += 1
            stack.append(root)
            on_stack.add(root)
            while work:
                node, it = work[-1]
                advanced = False
                for nxt in it:
                    if nxt not in index:
                        index[nxt] = low[nxt] = counter
                        counter += 1
                        stack.append(nxt)
                        on_stack.add(nxt)
                        work.append((nxt, iter(succ[nxt])))
                        advanced = True
                        break
                    if nxt in on_stack:
                        low[node] = min(low[node], index[nxt])
                if advanced:
                    continue
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        n = stack.pop()
                        on_stack.discard(n)
                        comp.append(n)
                        if n == node:
                            break
                    if len(comp) > 1:
                        out.append(sorted(comp))
        return sorted(out)

    @staticmethod
    def shortest_path(edges, start, goal):
        """The shortest path start -> ... -> goal over these edges (breadth-first; the first
        successor in name order wins a tie), at least one edge long; None if there is none."""
        succ = collections.defaultdict(list)
        for a, b in sorted(edges):
            succ[a].append(b)
        parent = {start: None}
        queue = collections.deque([start])
        while queue:
            node = queue.popleft()
            for nxt in succ[node]:
                if nxt == goal:
                    path = [node]
                    while parent[path[-1]] is not None:
                        path.append(parent[path[-1]])
                    return list(reversed(path)) + [goal]
                if nxt not in parent:
                    parent[nxt] = node
                    queue.append(nxt)
        return None

    def reasons(self, a, b):
        e = self.edges[(a, b)]
        return ', '.join(sorted(e['calls']) + sorted(e['includes']))


def read_symbols(nm, obj):
    """(name, nm letter) of the object's symbols, from nm's POSIX format."""
    try:
        run = subprocess.run([nm, '-P', obj], capture_output=True, text=True, check=False)
    except OSError as e:
        raise Usage(f'cannot run {nm}: {e}')
    if run.returncode != 0:
        raise Usage(f'{nm} -P {obj} failed: {run.stderr.strip()}')
    for line in run.stdout.splitlines():
        parts = line.split()
        if len(parts) >= 2 and len(parts[1]) == 1:
            yield parts[0], parts[1]


def collect_objects(args):
    """[(object file, whether it was named rather than found in a directory)]"""
    objects = []
    for arg in args:
        for item in arg.split(';'):
            if not item:
                continue
            if os.path.isdir(item):
                for dirpath, dirnames, filenames in os.walk(item):
                    dirnames.sort()
                    objects += [
                        (os.path.join(dirpath, n), False)
                        for n in sorted(filenames)
                        if n.endswith(('.o', '.obj'))
                    ]
            elif os.path.isfile(item):
                objects.append((item, True))
            else:
                raise Usage(f'no object file or directory {item}')
    if not objects:
        raise Usage('no object file given (build the library first)')
    return objects


# -- the report --------------------------------------------------------------------------------


def shown(graph, node):
    """A file as printed: its path under src/, with its layer when the path does not name it."""
    layer = graph.layer_of.get(node)
    if '/' in node:
        return node if layer is not None else f'{node} [no layer]'
    return f'{node} [{layer}]' if layer else f'{node} [no layer]'


def report(graph, violations, cycles, out):
    for kind, node, why in graph.misplaced:
        print(f'{kind}: {node} ({why})', file=out)
    for kind, a, b in violations:
        line = f'{kind}: {shown(graph, a)} -> {shown(graph, b)} ({graph.reasons(a, b)})'
        back = graph.shortest_path(graph.edges, b, a)
        if back:
            line += f'; a cycle: {" -> ".join([a] + back)}'
        print(line, file=out)
    for path in cycles:
        hops = '; '.join(f'{a} -> {b}: {graph.reasons(a, b)}' for a, b in zip(path, path[1:]))
        print(f'cycle: {" -> ".join(path)} ({hops})', file=out)


def cycles_within(graph, edges):
    """Cycles of these edges that cover every edge lying on one: for each edge a -> b not yet
    on a reported cycle (in name order), the shortest cycle through it, as [a, b, ..., a]."""
    out, covered = [], set()
    for comp in graph.components(edges):
        members = set(comp)
        inside = {(a, b) for (a, b) in edges if a in members and b in members}
        for a, b in sorted(inside):
            if (a, b) in covered:
                continue
            path = [a] + graph.shortest_path(inside, b, a)
            covered |= set(zip(path, path[1:]))
            out.append(path)
    return out


def dot(graph, bad_edges, out):
    print('digraph layers {', file=out)
    # the edges point down, from a file to the lower files it uses: top to bottom, core last
    print('  node [shape=box, fontname="Helvetica", fontsize=10];', file=out)
    for i, names in enumerate(graph.layers.levels):
        for layer in names:
            print(f'  subgraph "cluster_{layer}" {{ label="{layer} (level {i})";', file=out)
            for node in graph.nodes:
                if graph.layer_of[node] == layer:
                    print(f'    "{node}" [label="{node.rsplit("/", 1)[-1]}"];', file=out)
            print('  }', file=out)
    for node in graph.nodes:
        if graph.layer_of[node] is None:
            print(f'  "{node}" [color=red];', file=out)
    for (a, b), e in sorted(graph.edges.items()):
        attrs = ['color=red'] if (a, b) in bad_edges else []
        if not e['calls']:
            attrs.append('style=dashed')
        print(f'  "{a}" -> "{b}" [{", ".join(attrs)}];', file=out)
    print('}', file=out)


PICTURE_KEY = 'stabdae-layers'  # the PNG text chunk holding the drawn graph
HEADER_LAYERS_ABOVE = ('umbrella', 'fmi')  # public headers' layers above layers.txt's, in order
HEADER_LAYER_RE = re.compile(r'\(layer: ([A-Za-z0-9_.-]+)')
COMMENT_RE = re.compile(r'/\*.*?\*/', re.S)


def header_violations(layers, include_dir):
    """[(kind, header, explanation)] of the public headers in include_dir (a header whose first
    comments name no layer, or an unknown one; an include that goes up or sideways), and how
    many headers were read."""
    level_of = dict(layers.level_of)
    for i, name in enumerate(HEADER_LAYERS_ABOVE):
        level_of[name] = len(layers.levels) + i
    try:
        names = sorted(n for n in os.listdir(include_dir) if n.endswith('.h'))
    except OSError as e:
        raise Usage(f'cannot read the public headers in {include_dir}: {e.strerror}') from e
    if not names:
        raise Usage(f'no public header in {include_dir}')
    texts, layer_of, out = {}, {}, []
    for name in names:
        with open(os.path.join(include_dir, name), encoding='utf-8') as f:
            texts[name] = f.read()
        comments = COMMENT_RE.findall(texts[name])[:2]
        found = [m.group(1) for c in comments for m in HEADER_LAYER_RE.finditer(c)]
        if not found or found[0] not in level_of:
            what = f'"{found[0]}" is no layer' if found else 'its first comment names no layer'
            out.append(('undeclared', f'<stabdae/{name}>', what))
            continue
        layer_of[name] = found[0]
    for name in names:
        if name not in layer_of:
            continue
        for line in texts[name].splitlines():
            m = INCLUDE_RE.match(line)
            written = m and (m.group(1) or m.group(2))
            target = written and os.path.basename(written)
            if not target or target not in layer_of or written not in (target, f'stabdae/{target}'):
                continue
            la, lb = level_of[layer_of[name]], level_of[layer_of[target]]
            kind = (
                'up'
                if lb > la
                else 'sideways'
                if lb == la and layer_of[name] != layer_of[target]
                else None
            )
            if kind:
                out.append(
                    (
                        kind,
                        f'<stabdae/{name}> -> <stabdae/{target}>',
                        f'{layer_of[name]} includes {layer_of[target]}',
                    )
                )
    return out, len(names)


def graph_text(graph, bad_edges):
    """The graph a picture shows, one line each: the levels, every file with its layer, every
    edge with its kind (call or include) and whether it breaks the rule."""
    lines = [f'levels {graph.layers.order()}']
    lines += [f'file {n} {graph.layer_of[n]}' for n in sorted(graph.nodes)]
    for (a, b), e in sorted(graph.edges.items()):
        kind = 'call' if e['calls'] else 'include'
        lines.append(f'edge {a} {b} {kind}{" bad" if (a, b) in bad_edges else ""}')
    return '\n'.join(lines)


def png_text(path):
    """The text chunks (tEXt, zTXt, iTXt uncompressed or compressed) of a PNG, by keyword."""
    try:
        with open(path, 'rb') as f:
            data = f.read()
    except OSError as e:
        raise Usage(f'cannot read the picture {path}: {e.strerror}') from e
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise Usage(f'{path} is not a PNG')
    chunks, at = {}, 8
    while at + 8 <= len(data):
        length, kind = struct.unpack('>I4s', data[at : at + 8])
        body = data[at + 8 : at + 8 + length]
        at += 12 + length
        if kind == b'tEXt':
            key, _, text = body.partition(b'\0')
            chunks[key.decode('latin-1')] = text.decode('latin-1')
        elif kind == b'zTXt':
            key, _, rest = body.partition(b'\0')
            chunks[key.decode('latin-1')] = zlib.decompress(rest[1:]).decode('latin-1')
        elif kind == b'iTXt':
            key, _, rest = body.partition(b'\0')
            compressed, rest = rest[0], rest[2:]
            _, _, rest = rest.partition(b'\0')  # language tag
            _, _, text = rest.partition(b'\0')  # translated keyword
            chunks[key.decode('latin-1')] = (zlib.decompress(text) if compressed else text).decode(
                'utf-8'
            )
    return chunks


def picture_differs(graph, bad_edges, path, out):
    """Lines the picture at path shows and the code does not (-) or the code has and the
    picture does not (+); True when there are any."""
    drawn = png_text(path).get(PICTURE_KEY)
    if drawn is None:
        print(
            f'layers: {path} holds no graph (drawn by another tool, or before --draw kept it)',
            file=out,
        )
        return True
    have, want = set(drawn.splitlines()), set(graph_text(graph, bad_edges).splitlines())
    for line in sorted(have - want):
        print(f'layers: picture only: {line}', file=out)
    for line in sorted(want - have):
        print(f'layers: code only: {line}', file=out)
    return have != want


def draw(graph, bad_edges, path):
    """The levels as horizontal bands, bottom first; sibling layers side by side in a band; one
    box per file; an arrow per file-to-file edge (solid: a call, with or without an include;
    dashed: an include alone), red when it breaks the rule."""
    import matplotlib

    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.patches import FancyArrowPatch, FancyBboxPatch, Rectangle

    levels = graph.layers.levels
    rows = []  # per level: [(layer, [node, ...]), ...]
    for names in levels:
        rows.append(
            [(layer, [n for n in graph.nodes if graph.layer_of[n] == layer]) for layer in names]
        )
    stray = [n for n in graph.nodes if graph.layer_of[n] is None]
    if stray:
        rows.append([('(no layer)', stray)])

    # Order each layer's boxes by the mean position of their neighbours (a few sweeps up and
    # down), which shortens the arrows and uncrosses most of them.
    neighbours = collections.defaultdict(list)
    for a, b in graph.edges:
        neighbours[a].append(b)
        neighbours[b].append(a)

    def positions():
        pos = {}
        for row in rows:
            count = sum(len(ns) for _, ns in row) + len(row) - 1
            k = 0
            for _, ns in row:
                for n in ns:
                    pos[n] = (k + 0.5) / max(count, 1)
                    k += 1
                k += 1  # a gap between sibling layers
        return pos

    for sweep in range(8):
        pos = positions()
        order = range(len(rows)) if sweep % 2 == 0 else reversed(range(len(rows)))
        for r in order:
            for _, ns in rows[r]:

                def key(n):
                    xs = [pos[m] for m in neighbours[n] if m in pos]
                    return (sum(xs) / len(xs) if xs else pos[n], n)

                ns.sort(key=key)
                pos = positions()

    widest = max(1, max(sum(len(ns) for _, ns in row) + len(row) - 1 for row in rows))
    left = 1.7  # the column of the levels' names
    usable = max(11.0, 1.65 * widest)
    band, box_h = 1.6, 0.42
    box_w = min(1.4, 0.86 * usable / widest)
    width, height = left + usable, band * len(rows)
    fig, ax = plt.subplots(figsize=(width, height + 0.8))
    ax.set_xlim(0, width)
    ax.set_ylim(-0.8, height)
    ax.axis('off')

    xy = {}
    for r, row in enumerate(rows):
        y0 = r * band
        ax.add_patch(
            Rectangle((0, y0), width, band, color='#f2f2f2' if r % 2 else '#e6ecf4', zorder=0)
        )
        count = sum(len(ns) for _, ns in row) + len(row) - 1
        step = usable / max(count, 1)
        k = 0
        for g, (layer, ns) in enumerate(row):
            if len(row) > 1:
                ax.text(
                    left + k * step + 0.1,
                    y0 + band - 0.08,
                    layer + '/',
                    ha='left',
                    va='top',
                    fontsize=10,
                    style='italic',
                    color='#444',
                )
            for n in ns:
                xy[n] = (left + k * step + step / 2, y0 + band / 2)
                k += 1
            if g < len(row) - 1:
                ax.plot(
                    [left + k * step + step / 2] * 2,
                    [y0 + 0.1, y0 + band - 0.1],
                    color='#888',
                    lw=1,
                    ls=':',
                )
            k += 1
        ax.text(
            0.15,
            y0 + band / 2,
            ' | '.join(layer for layer, _ in row),
            ha='left',
            va='center',
            fontsize=12,
            weight='bold',
            color='#234',
        )

    # Each arrow leaves and reaches a box at its own point of the box's top or bottom edge, in
    # the order of where the arrow's other end lies, so that arrowheads never hide each other.
    sides = {}
    for a, b in graph.edges:
        (xa, ya), (xb, yb) = xy[a], xy[b]
        if abs(ya - yb) < 1e-9:  # within a band: rightwards above, leftwards below
            sides[(a, b)] = ('top', 'top') if xb > xa else ('bottom', 'bottom')
        else:
            sides[(a, b)] = ('bottom', 'top') if yb < ya else ('top', 'bottom')
    ports = collections.defaultdict(list)
    for (a, b), (sa, sb) in sides.items():
        ports[(a, sa)].append((xy[b][0], b, (a, b, 0)))
        ports[(b, sb)].append((xy[a][0], a, (a, b, 1)))
    at = {}
    for (node, side), ends in ports.items():
        ends.sort()
        x, y = xy[node]
        for i, (_, _, key) in enumerate(ends):
            at[key] = (
                x - 0.4 * box_w + 0.8 * box_w * (i + 1) / (len(ends) + 1),
                y + (box_h / 2 if side == 'top' else -box_h / 2),
            )

    for (a, b), e in sorted(graph.edges.items()):
        start, end = at[(a, b, 0)], at[(a, b, 1)]
        bad = (a, b) in bad_edges
        if sides[(a, b)][0] == sides[(a, b)][1]:
            # a pair of files that call each other: one arc above, one below; each stays in
            # its band
            rad = -min(0.3, 0.9 / max(abs(end[0] - start[0]), 1e-9))
        else:
            rad = 0.08
        ax.add_patch(
            FancyArrowPatch(
                start,
                end,
                connectionstyle=f'arc3,rad={rad}',
                arrowstyle='-|>',
                mutation_scale=9,
                lw=1.6 if bad else 0.7,
                color='#d62728' if bad else '#4a6b8a',
                alpha=0.95 if bad else 0.45,
                ls='-' if e['calls'] else '--',
                zorder=3 if bad else 1,
                shrinkA=0,
                shrinkB=1,
            )
        )

    for n, (x, y) in xy.items():
        header = n.endswith('.h')
        ax.add_patch(
            FancyBboxPatch(
                (x - box_w / 2, y - box_h / 2),
                box_w,
                box_h,
                boxstyle='round,pad=0.02,rounding_size=0.06',
                fc='#fffbe6' if header else 'white',
                ec='#d62728' if graph.layer_of[n] is None else '#345',
                lw=1,
                zorder=4,
            )
        )
        label = n.rsplit('/', 1)[-1]
        ax.text(
            x,
            y,
            label,
            ha='center',
            va='center',
            fontsize=9 if len(label) <= 14 else 8,
            zorder=5,
            family='monospace',
        )

    ax.text(
        0.15,
        -0.4,
        'The levels of src/layers.txt, bottom first; a box per file of src/ (a header counts '
        'as its .c; yellow: a header without one).\nAn arrow per dependency between two '
        'files: solid, a call or a reference (nm); dashed, an #include alone. '
        'Red: an edge that goes up, sideways or round a cycle.',
        fontsize=9,
        ha='left',
        va='center',
        color='#333',
        linespacing=1.5,
    )
    fig.savefig(
        path,
        dpi=110,
        bbox_inches='tight',
        metadata={PICTURE_KEY: graph_text(graph, bad_edges), 'Software': 'tools/layers'},
    )
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(
        prog='layers',
        description='Checks the layer rule of src/ (src/layers.txt) on the '
        'object files\' symbols and the includes; exit 1 on any violation.',
    )
    ap.add_argument('--src', default='src', help='the source tree (default: src)')
    ap.add_argument(
        '--objects',
        nargs='+',
        required=True,
        metavar='OBJ',
        help='object files or directories of them (a ;-list is split)',
    )
    ap.add_argument('--layers', help='the declaration (default: SRC/layers.txt)')
    ap.add_argument('--nm', default=os.environ.get('NM', 'nm'), help='nm (default: $NM or nm)')
    ap.add_argument(
        '--include', metavar='DIR', help='the public headers to check as well (include/stabdae)'
    )
    out = ap.add_mutually_exclusive_group()
    out.add_argument('--dot', action='store_true', help='print the graph as Graphviz text')
    out.add_argument('--draw', metavar='PNG', help='draw the graph (needs matplotlib)')
    out.add_argument(
        '--picture', metavar='PNG', help='exit 1 when the drawn graph in PNG is not the code\'s'
    )
    args = ap.parse_args(argv)

    try:
        if not os.path.isdir(args.src):
            raise Usage(f'no source tree {args.src}')
        layers = Layers(args.layers or os.path.join(args.src, 'layers.txt'))
        graph = Graph(args.src, layers)
        graph.scan_sources()
        graph.scan_includes()
        uncompiled = graph.scan_objects(collect_objects(args.objects), args.nm)
        headers, n_headers = header_violations(layers, args.include) if args.include else ([], 0)
    except Usage as e:
        print(f'layers: {e}', file=sys.stderr)
        return 2
    for s in uncompiled:
        print(f'layers: note: no object for {s} (only its includes count)', file=sys.stderr)

    violations = graph.layer_violations()
    bad_edges = {(a, b) for _, a, b in violations}
    # A cycle through two layers has an upward or sideways edge, reported as such (with the way
    # back); without those edges, what cycles remain lie within one layer, reported as cycles.
    cycles = cycles_within(graph, {e for e in graph.edges if e not in bad_edges})
    for path in cycles:
        bad_edges |= set(zip(path, path[1:]))

    if args.dot:
        dot(graph, bad_edges, sys.stdout)
    if args.draw:
        draw(graph, bad_edges, args.draw)
    out = sys.stderr if args.dot else sys.stdout
    if args.picture:
        try:
            stale = picture_differs(graph, bad_edges, args.picture, out)
        except Usage as e:
            print(f'layers: {e}', file=sys.stderr)
            return 2
        if stale:
            print(
                f'layers: {args.picture} is not the code\'s graph: redraw it with --draw '
                f'{args.picture} (docs/architecture.md, the picture)',
                file=out,
            )
            return 1
    report(graph, violations, cycles, out)
    for kind, header, why in headers:
        print(f'{kind}: {header} ({why})', file=out)
    total = len(graph.misplaced) + len(violations) + len(cycles) + len(headers)
    counts = collections.Counter(kind for kind, _, _ in violations + headers)
    size = (
        f'{len(graph.nodes)} files, {len(graph.edges)} edges, {len(layers.levels)} levels '
        f'({layers.order()})'
    )
    if args.include:
        size += f', {n_headers} public headers'

    if total:
        print(
            f'layers: {total} violations (up {counts["up"]}, sideways {counts["sideways"]}, '
            f'cycles {len(cycles)}, outside the layers '
            f'{len(graph.misplaced) + counts["undeclared"]}) in {size}',
            file=out,
        )
        return 1
    print(f'layers: clean: {size}', file=out)
    return 0
