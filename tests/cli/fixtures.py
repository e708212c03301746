# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Fixture meshes for the selfcol-cli tests, their writers in every format,
and an independent brute-force computation of the contact sets (the
definitions of docs/contract.md section 1, in plain Python floats) to hold the
tool's output to. Standard library only."""

import math
import random
import struct
from fractions import Fraction


def f32(x):
    """x rounded to float32, so that every format (STL is float32) holds it exactly."""
    return struct.unpack('<f', struct.pack('<f', x))[0]


def grid_sheet(nu, nv, surface, jitter=0.0, seed=1, quads=False):
    """A (nu x nv)-quad grid mapped by surface(u, v) -> (x, y, z), with
    float32 coordinates and a random jitter (generic positions: no exact ties
    for the predicates). Returns (positions, triangles[, quads])."""
    rng = random.Random(seed)
    pos = []
    for j in range(nv + 1):
        for i in range(nu + 1):
            x, y, z = surface(i / nu, j / nv)
            pos.append(tuple(f32(c + rng.uniform(-jitter, jitter)) for c in (x, y, z)))
    tris, polys = [], []
    for j in range(nv):
        for i in range(nu):
            a = j * (nu + 1) + i
            b, c, d = a + 1, a + nu + 2, a + nu + 1
            polys.append((a, b, c, d))
            # The fan of (a b c d), as the tool triangulates quads.
            tris.append((a, b, c))
            tris.append((a, c, d))
    return (pos, tris, polys) if quads else (pos, tris)


def figure_eight(u, v):
    """A sheet whose cross-section is a figure eight: it passes through itself."""
    t = 2 * math.pi * (-0.1 + 0.7 * u)
    return (0.5 * math.sin(t), 0.6 * v, 0.25 * math.sin(2 * t))


def flat(u, v):
    return (u, v, 0.0)


def wavy(u, v):
    return (u, v, 0.05 * math.sin(2 * math.pi * u))


# ---------------------------------------------------------------------------
# Writers. Triangle lists use 0-based indices; OBJ writes them 1-based.

def write_obj(path, pos, faces, style='plain', newline='\n'):
    lines = ['# selfcol-cli test fixture']
    for p in pos:
        lines.append('v %r %r %r' % p)
    lines.append('vt 0 0')
    lines.append('vn 0 0 1')
    n = len(pos)
    for f in faces:
        if style == 'slashes':
            lines.append('f ' + ' '.join('%d/1/1' % (i + 1) for i in f))
        elif style == 'negative':  # relative indices: all vertices come first
            lines.append('f ' + ' '.join('%d//1' % (i - n) for i in f))
        else:
            lines.append('f ' + ' '.join('%d' % (i + 1) for i in f))
    with open(path, 'w', newline='') as out:
        out.write(newline.join(lines) + newline)


PLY_TYPES = {'char': 'b', 'uchar': 'B', 'short': 'h', 'ushort': 'H', 'int': 'i', 'uint': 'I',
             'float': 'f', 'double': 'd'}


def write_ply(path, pos, faces, encoding='ascii', coord='float', count_type='uchar',
              index_type='int', extras=False):
    """PLY in any encoding; extras adds per-vertex normals and colours and an
    element the reader must skip (with a list property)."""
    head = ['ply', 'format %s 1.0' % encoding, 'comment fixture',
            'element vertex %d' % len(pos)]
    head += ['property %s %s' % (coord, a) for a in 'xyz']
    if extras:
        head += ['property float nx', 'property uchar red']
    head += ['element face %d' % len(faces),
             'property list %s %s vertex_indices' % (count_type, index_type)]
    if extras:
        head += ['property uchar flags', 'element material 2', 'property list uchar int ids',
                 'property double weight']
    head.append('end_header')
    with open(path, 'wb') as out:
        out.write(('\n'.join(head) + '\n').encode())
        if encoding == 'ascii':
            body = []
            for p in pos:
                body.append('%r %r %r' % p + (' 0.5 200' if extras else ''))
            for f in faces:
                body.append('%d ' % len(f) + ' '.join(str(i) for i in f) + (' 7' if extras else ''))
            if extras:
                body += ['2 1 2 0.5', '0 1.5']
            out.write(('\n'.join(body) + '\n').encode())
            return
        e = '<' if encoding == 'binary_little_endian' else '>'
        c = PLY_TYPES[coord]
        for p in pos:
            out.write(struct.pack(e + c * 3, *p))
            if extras:
                out.write(struct.pack(e + 'fB', 0.5, 200))
        for f in faces:
            out.write(struct.pack(e + PLY_TYPES[count_type] + PLY_TYPES[index_type] * len(f),
                                  len(f), *f))
            if extras:
                out.write(struct.pack(e + 'B', 7))
        if extras:
            out.write(struct.pack(e + 'Biid', 2, 1, 2, 0.5))
            out.write(struct.pack(e + 'Bd', 0, 1.5))


def write_off(path, pos, faces):
    with open(path, 'w') as out:
        out.write('OFF\n# comment\n%d %d 0\n' % (len(pos), len(faces)))
        for p in pos:
            out.write('%r %r %r\n' % p)
        for f in faces:
            out.write('%d %s\n' % (len(f), ' '.join(str(i) for i in f)))


def write_stl_ascii(path, pos, tris):
    with open(path, 'w') as out:
        out.write('solid fixture\n')
        for t in tris:
            out.write('  facet normal 0 0 1\n    outer loop\n')
            for i in t:
                out.write('      vertex %r %r %r\n' % pos[i])
            out.write('    endloop\n  endfacet\n')
        out.write('endsolid fixture\n')


def write_stl_binary(path, pos, tris):
    with open(path, 'wb') as out:
        out.write(b'solid but binary'.ljust(80, b' '))  # binary files may say "solid" too
        out.write(struct.pack('<I', len(tris)))
        for t in tris:
            out.write(struct.pack('<3f', 0, 0, 1))
            for i in t:
                out.write(struct.pack('<3f', *pos[i]))
            out.write(struct.pack('<H', 0))


# ---------------------------------------------------------------------------
# Brute force, straight from the definitions.

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def point_segment(p, a, b):
    ab = sub(b, a)
    denom = dot(ab, ab)
    t = 0.0 if denom == 0 else max(0.0, min(1.0, dot(sub(p, a), ab) / denom))
    q = (a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2])
    return math.sqrt(dot(sub(p, q), sub(p, q)))


def point_triangle(p, a, b, c):
    """Distance from p to the closed triangle abc (a segment if it is flat)."""
    n = cross(sub(b, a), sub(c, a))
    nn = dot(n, n)
    edges = min(point_segment(p, a, b), point_segment(p, b, c), point_segment(p, c, a))
    if nn == 0:
        return edges
    # Inside test on the projection of p onto the plane.
    ap = sub(p, a)
    s = dot(ap, n) / nn
    q = (p[0] - s * n[0], p[1] - s * n[1], p[2] - s * n[2])
    inside = all(dot(cross(sub(y, x), sub(q, x)), n) >= 0 for x, y in ((a, b), (b, c), (c, a)))
    return min(abs(s) * math.sqrt(nn), edges) if inside else edges


def segment_segment(p1, q1, p2, q2):
    """Distance between two closed segments (sampled minimisation would be
    inexact: this is the clamped closed form, with the parallel case
    covered by the four endpoint distances)."""
    d1, d2, r = sub(q1, p1), sub(q2, p2), sub(p1, p2)
    a, e, f = dot(d1, d1), dot(d2, d2), dot(d2, r)
    c, b = dot(d1, r), dot(d1, d2)
    best = min(point_segment(p1, p2, q2), point_segment(q1, p2, q2),
               point_segment(p2, p1, q1), point_segment(q2, p1, q1))
    denom = a * e - b * b
    if a > 0 and e > 0 and denom > 1e-300:
        s = (b * f - c * e) / denom
        t = (a * f - b * c) / denom
        if 0 <= s <= 1 and 0 <= t <= 1:
            x = (p1[0] + s * d1[0], p1[1] + s * d1[1], p1[2] + s * d1[2])
            y = (p2[0] + t * d2[0], p2[1] + t * d2[1], p2[2] + t * d2[2])
            best = min(best, math.sqrt(dot(sub(x, y), sub(x, y))))
    return best


def orient(a, b, c, d):
    """Sign-exact when given Fractions: the orientation of d against plane abc."""
    return dot(cross(sub(b, a), sub(c, a)), sub(d, a))


def crosses(p, q, a, b, c):
    """Edge pq crosses triangle abc (contacts.h): its endpoints strictly on
    opposite sides of the plane of abc, and the line through pq meets the
    closed triangle. Decided exactly: the points are Fractions (every double
    is one), so there is no rounding and no ambiguity; a flat triangle has
    every orientation 0 and is never crossed."""
    o1, o2 = orient(a, b, c, p), orient(a, b, c, q)
    if o1 == 0 or o2 == 0 or (o1 > 0) == (o2 > 0):
        return False
    s = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)]
    return all(x >= 0 for x in s) or all(x <= 0 for x in s)


def edges_of(tris):
    edges = set()
    for t in tris:
        for k in range(3):
            a, b = t[k], t[(k + 1) % 3]
            if a != b:
                edges.add((min(a, b), max(a, b)))
    return sorted(edges)


def read_simple_obj(path):
    """Positions and triangles of a plain OBJ ('v x y z', 'f a b c' 1-based
    triangles), the test's own reading, independent of the tool's."""
    pos, tris = [], []
    for line in open(path):
        w = line.split()
        if w and w[0] == 'v':
            pos.append(tuple(float(x) for x in w[1:4]))
        elif w and w[0] == 'f':
            idx = [int(x.split('/')[0]) - 1 for x in w[1:]]
            tris += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return pos, tris


def brute_force(meshes, d):
    """Contact sets of one mesh with itself, or of two meshes (self and
    between), in the tool's output indexing (second mesh after the first).
    Returns (sets, ambiguous) where ambiguous holds the proximities whose
    float distance is within a relative 1e-6 of d (left out of comparisons:
    the contract lets them fall either way); interferences are exact."""
    pos, tris, owner = [], [], []
    for m, (p, t) in enumerate(meshes):
        off = len(pos)
        pos += p
        tris += [tuple(i + off for i in tri) for tri in t]
        owner += [m] * len(p)
    edges = edges_of(tris)
    used = sorted({i for t in tris for i in t})
    sets = {'vf': set(), 'ee': set(), 'ef': set(), 'intersecting_triangles': set()}
    amb = {k: set() for k in sets}
    tol = 1e-6 * d

    # Only to save time: two point sets whose boxes are farther apart than
    # `gap` on some axis are farther apart than gap (a conservative skip).
    def box(ids):
        return tuple((min(pos[i][k] for i in ids), max(pos[i][k] for i in ids)) for k in range(3))

    def apart(b1, b2, gap):
        return any(b1[k][0] > b2[k][1] + gap or b2[k][0] > b1[k][1] + gap for k in range(3))

    tri_box = [box(t) for t in tris]
    margin = 2 * d + 1e-12

    def same_mesh(i, j):
        return owner[i] == owner[j]

    for v in used:
        vb = box([v])
        for ti, t in enumerate(tris):
            if same_mesh(v, t[0]) and v in t or apart(vb, tri_box[ti], margin):
                continue
            dist = point_triangle(pos[v], *(pos[i] for i in t))
            if abs(dist - d) <= tol:
                amb['vf'].add((v, ti))
            elif dist < d:
                sets['vf'].add((v, ti))
    edge_box = {e: box(e) for e in edges}
    for i, e in enumerate(edges):
        for f in edges[i + 1:]:
            if same_mesh(e[0], f[0]) and set(e) & set(f) or apart(edge_box[e], edge_box[f], margin):
                continue
            dist = segment_segment(pos[e[0]], pos[e[1]], pos[f[0]], pos[f[1]])
            key = e + f
            if abs(dist - d) <= tol:
                amb['ee'].add(key)
            elif dist < d:
                sets['ee'].add(key)

    exact = [tuple(Fraction(x) for x in p) for p in pos]

    def edge_crosses(e, t):
        if same_mesh(e[0], t[0]) and set(e) & set(t):
            return False
        return crosses(exact[e[0]], exact[e[1]], *(exact[i] for i in t))

    for e in edges:
        for ti, t in enumerate(tris):
            if apart(edge_box[e], tri_box[ti], 1e-12):
                continue
            if edge_crosses(e, t):
                sets['ef'].add(e + (ti,))
    # Intersecting triangles, per triangle pair: an edge of one crosses the other.
    for si, s in enumerate(tris):
        s_edges = [(min(s[k], s[(k + 1) % 3]), max(s[k], s[(k + 1) % 3])) for k in range(3)]
        for ti in range(si + 1, len(tris)):
            if apart(tri_box[si], tri_box[ti], 1e-12):
                continue
            t = tris[ti]
            t_edges = [(min(t[k], t[(k + 1) % 3]), max(t[k], t[(k + 1) % 3])) for k in range(3)]
            if any(edge_crosses(e, t) for e in s_edges) or any(edge_crosses(e, s) for e in t_edges):
                sets['intersecting_triangles'].add((si, ti))
    return sets, amb
