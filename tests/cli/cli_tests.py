# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Tests of the selfcol-cli binary (run by ctest, one test per function).

usage: cli_tests.py TEST --cli BINARY --work DIR --source DIR [--shared DIR]

Correctness is judged against fixtures.brute_force(), an independent Python
computation of the contact sets from their definitions, never against
numbers produced by the code under test. Exit 0: pass, 1: fail, 77: skipped.
"""

import argparse
import glob
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

sys.dont_write_bytecode = True  # keep the source tree clean
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fixtures as fx  # noqa: E402

SKIP = 77
ARGS = None
KEYS = ('vf', 'ee', 'ef', 'intersecting_triangles')
METHODS = ('exact', 'bvh', 'exhaustive', 'seed', 'cone')
EXACT_METHODS = ('exact', 'bvh', 'exhaustive')


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def work(name):
    path = os.path.join(ARGS.work, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    return path


def run(*args, expect=None):
    """Runs the tool; returns (status, stdout, stderr)."""
    proc = subprocess.run([ARGS.cli] + [str(a) for a in args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, timeout=600)
    out, err = proc.stdout.decode(), proc.stderr.decode()
    if expect is not None and proc.returncode != expect:
        raise Failure('%s: exit status %d, expected %d\nstdout: %s\nstderr: %s'
                      % (' '.join(map(str, args)), proc.returncode, expect, out[:2000], err))
    return proc.returncode, out, err


def check_json(*args, expect=None):
    """Runs check with --json - and returns the parsed objects (one per line)."""
    status, out, _ = run('check', '--json', '-', *args, expect=expect)
    return status, [json.loads(line) for line in out.splitlines() if line.strip()]


def as_sets(obj):
    return {k: {tuple(x) for x in obj[k]} for k in KEYS}


def compare(got, want, ambiguous, what):
    for k in KEYS:
        g = got[k] - ambiguous[k]
        w = want[k] - ambiguous[k]
        check(g == w, '%s: %s differs from the brute force: missing %s, extra %s'
              % (what, k, sorted(w - g)[:8], sorted(g - w)[:8]))


def figure_eight_mesh(quads=False):
    return fx.grid_sheet(12, 5, fx.figure_eight, jitter=0.004, seed=7, quads=quads)


def mean_edge(meshes):
    total, count = 0.0, 0
    for pos, tris in meshes:
        for a, b in fx.edges_of(tris):
            total += fx.point_segment(pos[a], pos[b], pos[b])
            count += 1
    return total / count


# ---------------------------------------------------------------------------

def test_help_version():
    for cmd in (['--help'], ['check', '--help'], ['info', '--help'], ['check', '-h']):
        _, out, _ = run(*cmd, expect=0)
        check('usage: selfcol-cli' in out, '%s: no usage text' % cmd)
    _, out, _ = run('check', '--help', expect=0)
    for option in ('--distance', '--distance-rel', '--method', '--narrow', '--json', '--csv',
                   '--mark', '--png', '--quiet', '--fail-on', '--threads'):
        check(option in out, 'check --help does not mention %s' % option)
    header = open(os.path.join(ARGS.source, 'include', 'selfcol', 'version.h')).read()
    version = '.'.join(re.search(r'#define SELFCOL_VERSION_%s (\d+)' % p, header).group(1)
                       for p in ('MAJOR', 'MINOR', 'PATCH'))
    for cmd in (['--version'], ['check', '--version']):
        _, out, _ = run(*cmd, expect=0)
        check(out.strip() == 'selfcol-cli ' + version, '--version printed %r' % out)


def test_exit_status():
    pos, tris = figure_eight_mesh()
    fx.write_obj(work('exit/eight.obj'), pos, tris)
    pos2, tris2 = fx.grid_sheet(6, 6, fx.wavy, jitter=0.001, seed=3)
    fx.write_obj(work('exit/sheet.obj'), pos2, tris2)
    run('check', work('exit/eight.obj'), expect=1)
    run('check', '--quiet', work('exit/sheet.obj'), expect=0)
    # Two parallel sheets closer than d but not crossing: proximities only.
    e = 1.0 / 6
    lifted = [(x, y, fx.f32(z + 0.05 * e)) for x, y, z in pos2]
    fx.write_obj(work('exit/lifted.obj'), lifted, tris2)
    _, objs = check_json(work('exit/sheet.obj'), work('exit/lifted.obj'), expect=0)
    check(objs[0]['counts']['vf'] > 0 and objs[0]['counts']['ef'] == 0,
          'parallel sheets: expected proximities only, got %s' % objs[0]['counts'])
    run('check', '--fail-on', 'proximity', work('exit/sheet.obj'), work('exit/lifted.obj'),
        expect=1)
    run('check', '--fail-on=interference', work('exit/sheet.obj'), work('exit/lifted.obj'),
        expect=0)
    sheet = work('exit/sheet.obj')
    usage = [[], ['frobnicate'], ['check'], ['check', '--method', 'fast', sheet],
             ['check', '--narrow', 'gjk', sheet], ['check', '--distance', '-1', sheet],
             ['check', '--distance', '1', '--distance-rel', '0.1', sheet],
             ['check', '--bogus', sheet], ['check', sheet, '--json'],
             ['check', sheet, sheet, sheet], ['check', '--range', '0:3', sheet],
             ['check', '--range', '3:1', work('exit/f%d.obj')], ['check', '--threads', '0', sheet],
             ['check', '--size', '10x10', sheet], ['check', '--view', 'north', sheet],
             ['check', '--fail-on', 'warning', sheet], ['info'], ['info', '--method', 'bvh', sheet],
             ['check', '--json', '-', '--csv', '-', sheet]]
    for args in usage:
        status, out, err = run(*args)
        check(status == 2, '%s: exit %d, expected 2' % (args, status))
        check(err.strip() != '', '%s: no message on stderr' % args)


def test_json_schema():
    pos, tris = figure_eight_mesh()
    path = work('schema/eight.obj')
    fx.write_obj(path, pos, tris)
    pos2, tris2 = fx.grid_sheet(4, 4, fx.flat, seed=2)
    fx.write_obj(work('schema/flat.obj'), pos2, tris2)
    runs = [(check_json(path)[1], len(pos), len(tris)),
            (check_json('--distance', '0.02', '--method', 'bvh', path, work('schema/flat.obj'))[1],
             len(pos) + len(pos2), len(tris) + len(tris2))]
    for objs, nv, nt in runs:
        check(len(objs) == 1, 'expected one JSON object, got %d' % len(objs))
        o = objs[0]
        for key, kind in (('selfcol_version', str), ('files', list), ('distance', float),
                          ('method', str), ('narrow', str), ('counts', dict), ('stats', dict),
                          ('mean_edge_length', float)):
            check(isinstance(o.get(key), kind), 'key %s missing or not %s' % (key, kind.__name__))
        check(o['method'] in METHODS and o['narrow'] in ('closed', 'libccd'), 'method/narrow')
        check('frame' not in o, 'a single check has no frame key')
        widths = {'vf': 2, 'ee': 4, 'ef': 3, 'intersecting_triangles': 2}
        for k, width in widths.items():
            arr = o[k]
            check(isinstance(arr, list) and o['counts'][k] == len(arr), '%s count' % k)
            check(all(isinstance(x, list) and len(x) == width and
                      all(isinstance(i, int) and i >= 0 for i in x) for x in arr),
                  '%s entries are not %d non-negative integers' % (k, width))
            check(arr == sorted(arr), '%s is not sorted' % k)
            check(len({tuple(x) for x in arr}) == len(arr), '%s has duplicates' % k)
        check(all(v < nv and t < nt for v, t in o['vf']), 'vf index out of range')
        check(all(a0 < a1 and b0 < b1 and (a0, a1) < (b0, b1) and b1 < nv
                  for a0, a1, b0, b1 in o['ee']), 'ee edges not sorted pairs in ascending order')
        check(all(a0 < a1 < nv and t < nt for a0, a1, t in o['ef']), 'ef entries')
        check(all(t1 < t2 < nt for t1, t2 in o['intersecting_triangles']), 'triangle pairs')
        for key in ('vertices', 'triangles', 'edges', 'candidate_pairs', 'seconds'):
            check(key in o['stats'], 'stats.%s missing' % key)
        check(o['stats']['vertices'] == nv and o['stats']['triangles'] == nt, 'stats counts')
        for key in ('load', 'topology', 'hierarchy', 'query'):
            check(isinstance(o['stats']['seconds'][key], (int, float)), 'seconds.%s' % key)
    # info --json
    _, out, _ = run('info', '--json', '-', path, expect=0)
    info = json.loads(out)
    check(info['vertices'] == len(pos) and info['triangles'] == len(tris), 'info counts')
    check(info['boundary_loops'] == 1 and info['components'] == 1 and not info['closed'],
          'info topology of a sheet: %s' % info)
    check(info['consistently_oriented'] is True, 'the grid is consistently oriented')
    check(info['edges'] == len(fx.edges_of(tris)), 'info edges')


def run_against_brute_force(meshes, files, extra, what, kinds=KEYS):
    d = extra.get('distance') or 0.1 * mean_edge(meshes)
    want, amb = fx.brute_force(meshes, d)
    for k in kinds:  # the fixture must exercise what it is meant to
        check(len(want[k]) > 0, '%s: fixture without %s' % (what, k))
    expect_status = 1 if want['ef'] else 0
    results = {}
    for method in METHODS:
        args = ['--method', method] + (['--distance', repr(d)] if 'distance' in extra else [])
        status, objs = check_json(*(args + files))
        check(status == expect_status, '%s: exit %d' % (what, status))
        got = as_sets(objs[0])
        results[method] = got
        if method in EXACT_METHODS:
            compare(got, want, amb, '%s, method %s' % (what, method))
        else:  # not exact: may miss contacts, never reports a false one
            for k in KEYS:
                check(got[k] - amb[k] <= want[k], '%s: %s reports false %s' % (what, method, k))
        check(abs(objs[0]['distance'] - d) <= 1e-9 * d, '%s: distance %r, expected %r'
              % (what, objs[0]['distance'], d))
    args = ['--distance', repr(d)] if 'distance' in extra else []
    status, objs = check_json('--narrow', 'libccd', '--method', 'exhaustive', *(args + files))
    got = as_sets(objs[0])
    # libccd also reports edges that only touch a triangle (hierarchy.h): compare the rest.
    compare(got, want, amb, '%s, libccd' % what)
    return results


def test_exhaustive_matches_brute_force():
    pos, tris = figure_eight_mesh()
    fx.write_obj(work('brute/eight.obj'), pos, tris)
    run_against_brute_force([(pos, tris)], [work('brute/eight.obj')], {}, 'figure eight',
                            kinds=('ee', 'ef', 'intersecting_triangles'))
    # A larger distance: vertex-triangle proximities too.
    run_against_brute_force([(pos, tris)], [work('brute/eight.obj')], {'distance': 0.12},
                            'figure eight, d = 0.12')
    # Two meshes: a wavy sheet through the figure eight.
    pos2, tris2 = fx.grid_sheet(6, 4, lambda u, v: (u - 0.5, 0.1 + 0.4 * v, 0.03 + 0.1 * u),
                                jitter=0.003, seed=11)
    fx.write_ply(work('brute/plane.ply'), pos2, tris2, encoding='binary_little_endian')
    run_against_brute_force([(pos, tris), (pos2, tris2)],
                            [work('brute/eight.obj'), work('brute/plane.ply')], {},
                            'two meshes', kinds=('ee', 'ef', 'intersecting_triangles'))
    # Two parallel sheets closer than d: proximities between meshes only.
    pos3, tris3 = fx.grid_sheet(6, 6, fx.wavy, jitter=0.001, seed=3)
    lifted = [(x, y, fx.f32(z + 0.05 / 6)) for x, y, z in pos3]
    fx.write_off(work('brute/low.off'), pos3, tris3)
    fx.write_stl_binary(work('brute/high.stl'), lifted, tris3)
    high_file_pos = [lifted[i] for t in tris3 for i in t]  # STL: 3 file vertices per facet
    first = {}
    for i, p in enumerate(high_file_pos):
        first.setdefault(p, i)
    # The STL's vertices after welding: the lowest file index of each position.
    high = (high_file_pos, [tuple(first[lifted[i]] for i in t) for t in tris3])
    run_against_brute_force([(pos3, tris3), high], [work('brute/low.off'), work('brute/high.stl')],
                            {}, 'parallel sheets', kinds=('vf', 'ee'))


def canonical_by_position(obj, pos):
    """Contact sets with vertex indices replaced by positions (formats such as
    STL number vertices differently; triangles keep their order)."""
    out = {}
    out['vf'] = {(pos[v], t) for v, t in obj['vf']}
    out['ee'] = {frozenset([frozenset([pos[a], pos[b]]), frozenset([pos[c], pos[d]])])
                 for a, b, c, d in obj['ee']}
    out['ef'] = {(frozenset([pos[a], pos[b]]), t) for a, b, t in obj['ef']}
    out['intersecting_triangles'] = {tuple(x) for x in obj['intersecting_triangles']}
    return out


def test_formats_agree():
    pos, tris, quads = figure_eight_mesh(quads=True)
    d = work('formats/x')[:-1]
    files = {
        'obj': ('eight.obj', lambda p: fx.write_obj(p, pos, tris)),
        'obj quads': ('quads.obj', lambda p: fx.write_obj(p, pos, quads)),
        'obj v/vt/vn CRLF': ('slashes.obj', lambda p: fx.write_obj(p, pos, tris, 'slashes', '\r\n')),
        'obj negative': ('negative.obj', lambda p: fx.write_obj(p, pos, quads, 'negative')),
        'ply ascii': ('ascii.ply', lambda p: fx.write_ply(p, pos, tris)),
        'ply ascii extras': ('ascii_extras.ply', lambda p: fx.write_ply(p, pos, quads, extras=True)),
        'ply le float': ('le.ply', lambda p: fx.write_ply(p, pos, tris, 'binary_little_endian')),
        'ply le double uint16': ('le_d.ply', lambda p: fx.write_ply(
            p, pos, tris, 'binary_little_endian', 'double', 'uchar', 'ushort')),
        'ply be double': ('be_d.ply', lambda p: fx.write_ply(
            p, pos, quads, 'binary_big_endian', 'double', 'int', 'uint', extras=True)),
        'ply be float char': ('be_f.ply', lambda p: fx.write_ply(
            p, pos, tris, 'binary_big_endian', 'float', 'char', 'int')),
        'off': ('eight.off', lambda p: fx.write_off(p, pos, quads)),
        'stl ascii': ('ascii.stl', lambda p: fx.write_stl_ascii(p, pos, tris)),
        'stl binary': ('binary.stl', lambda p: fx.write_stl_binary(p, pos, tris)),
    }
    reference = None
    for what, (name, writer) in files.items():
        path = d + name
        writer(path)
        _, objs = check_json('--distance', '0.05', path)
        _, out, _ = run('info', '--json', '-', path, expect=0)
        info = json.loads(out)
        check(info['triangles'] == len(tris), '%s: %d triangles' % (what, info['triangles']))
        stl = what.startswith('stl')
        file_pos = [pos[i] for t in tris for i in t] if stl else pos
        check(info['vertices'] == len(file_pos), '%s: %d vertices' % (what, info['vertices']))
        check(info['used_vertices'] == len(pos), '%s: %d vertices after welding'
              % (what, info['used_vertices']))
        sets = canonical_by_position(objs[0], file_pos)
        if not stl:  # same indexing: the raw arrays must be identical
            raw = {k: objs[0][k] for k in KEYS}
            if reference is None:
                reference_raw = raw
            check(raw == reference_raw, '%s: index arrays differ from the OBJ file' % what)
        if reference is None:
            reference = sets
            check(len(objs[0]['ef']) > 0, 'the fixture must intersect itself')
        check(sets == reference, '%s: contacts differ from the OBJ file' % what)


def test_unwelded_twin():
    pos, tris = figure_eight_mesh()
    fx.write_obj(work('weld/welded.obj'), pos, tris)
    # Every triangle with its own three vertices, as STL or a UV-seamed export has them.
    split_pos = [pos[i] for t in tris for i in t]
    split_tris = [(3 * k, 3 * k + 1, 3 * k + 2) for k in range(len(tris))]
    fx.write_obj(work('weld/split.obj'), split_pos, split_tris)
    # Only a seam: the vertices of one grid column duplicated for the triangles right of it.
    seam_pos = list(pos)
    copy = {}
    seam_tris = []
    for t in tris:
        right = all(i % 13 >= 6 for i in t)
        nt = []
        for i in t:
            if right and i % 13 == 6:
                if i not in copy:
                    copy[i] = len(seam_pos)
                    seam_pos.append(pos[i])
                nt.append(copy[i])
            else:
                nt.append(i)
        seam_tris.append(tuple(nt))
    check(len(copy) > 0, 'the seam duplicates vertices')
    fx.write_obj(work('weld/seam.obj'), seam_pos, seam_tris)
    _, ref = check_json(work('weld/welded.obj'))
    ref_sets = canonical_by_position(ref[0], pos)
    for name, file_pos in (('split', split_pos), ('seam', seam_pos)):
        path = work('weld/%s.obj' % name)
        _, objs = check_json(path)
        check(canonical_by_position(objs[0], file_pos) == ref_sets,
              '%s OBJ: contacts differ from the welded twin' % name)
        # Indices name the lowest file index of each welded group.
        first = {}
        for i, p in enumerate(file_pos):
            first.setdefault(p, i)
        used = {v for v, _ in objs[0]['vf']} | {i for e in objs[0]['ee'] for i in e}
        check(all(first[file_pos[v]] == v for v in used),
              '%s OBJ: an index is not the lowest of its welded group' % name)
        # Without the weld, the split surface touches itself along every seam.
        _, raw = check_json('--no-weld', path)
        check(raw[0]['counts']['ee'] > ref[0]['counts']['ee'],
              '%s OBJ --no-weld: expected seam contacts' % name)


def write_bytes(name, data):
    path = work('bad/' + name)
    with open(path, 'wb') as out:
        out.write(data)
    return path


def make_fifo(path):
    if os.path.exists(path):
        os.remove(path)
    os.mkfifo(path)
    return path


def test_malformed_input():
    pos, tris = fx.grid_sheet(3, 3, fx.flat)
    ply = work('bad/good.ply')
    fx.write_ply(ply, pos, tris, 'binary_little_endian', 'double')
    good = open(ply, 'rb').read()
    header_end = good.index(b'end_header\n') + len(b'end_header\n')
    stl = work('bad/good.stl')
    fx.write_stl_binary(stl, pos, tris)
    stl_bytes = open(stl, 'rb').read()
    obj_head = b'v 0 0 0\nv 1 0 0\nv 0 1 0\n'
    nan_double = struct.pack('<d', float('nan'))
    bad_ply_index = bytearray(good)
    bad_ply_index[-4:] = struct.pack('<i', 99)  # last index of the last face
    cases = [
        # (file, substring expected in the message, line number or None)
        (write_bytes('nan.obj', obj_head + b'v nan 0 1\nf 1 2 3\n'), 'NaN', 4),
        (write_bytes('inf.obj', obj_head + b'f 1 2 3\nv 1e999 0 0\n'), 'infinite', 5),
        (write_bytes('range.obj', obj_head + b'f 1 2 3\nf 1 2 9\n'), 'out of range', 5),
        (write_bytes('negative.obj', obj_head + b'f -1 -2 -7\n'), 'out of range', 4),
        (write_bytes('zero.obj', obj_head + b'f 0 1 2\n'), 'index 0', 4),
        (write_bytes('two.obj', obj_head + b'f 1 2 3\nf 1 2\n'), 'fewer|at least 3', 5),
        (write_bytes('text.obj', obj_head + b'v 1 zero 2\nf 1 2 3\n'), 'not a number', 4),
        (write_bytes('short.obj', obj_head + b'v 1 2\nf 1 2 3\n'), 'too few', 4),
        (write_bytes('nul.obj', obj_head + b'f 1 2\x00 3\n'), 'NUL', 4),
        (write_bytes('novertex.obj', b'# nothing\nv 0 0 0\n'), 'no faces', None),
        # Hardening issue, defect 7: bare 'v' and 'f' lines were skipped silently.
        (write_bytes('bare_v.obj', obj_head + b'v\nf 1 2 3\n'), 'too few', 4),
        (write_bytes('bare_f.obj', obj_head + b'f 1 2 3\nf\n'), 'at least 3', 5),
        (write_bytes('bare_f_comment.obj', obj_head + b'f # nothing\n'), 'at least 3', 4),
        # Defect 5: coordinates beyond the library's range (2^200, or a whole
        # mesh below 2^-200) are refused, not answered wrongly.
        # The message names the coordinate and the limit (hardening 0.4).
        (write_bytes('huge.obj', b'v 0 0 0\nv 1e155 0 0\nv 0 1e155 0\nf 1 2 3\n'),
         r'vertex 1, coordinate x = 1e\+155 is beyond the largest coordinate magnitude 2\^200',
         None),
        (write_bytes('tiny.obj', b'v 0 0 0\nv 1e-200 0 0\nv 0 1e-200 0\nf 1 2 3\n'),
         r'vertex 1, coordinate x = 1e-200 is below the smallest nonzero coordinate magnitude',
         None),
        (write_bytes('empty.obj', b''), 'empty', None),
        (write_bytes('empty.ply', b''), 'empty', None),
        (write_bytes('truncated.ply', good[:len(good) - 7]), 'truncated', None),
        (write_bytes('truncated_vertices.ply', good[:header_end + 20]), 'truncated', None),
        (write_bytes('noheader.ply', good[:header_end - 12]), 'end_header', None),
        (write_bytes('range.ply', bytes(bad_ply_index)), 'out of range', None),
        (write_bytes('nan.ply', good[:header_end] + nan_double + good[header_end + 8:]),
         'NaN', None),
        (write_bytes('huge.ply', good.replace(b'element vertex 16', b'element vertex 99999999999')),
         'more than the file', None),
        (write_bytes('ascii_nan.ply', b'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n'
                     b'property float y\nproperty float z\nelement face 1\nproperty list uchar '
                     b'int vertex_indices\nend_header\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n'), 'NaN', 11),
        (write_bytes('ascii_two.ply', b'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n'
                     b'property float y\nproperty float z\nelement face 1\nproperty list uchar '
                     b'int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n'), 'at least 3',
         13),
        # Found by the fuzzer: a second vertex element overflowed the first's array.
        (write_bytes('twice.ply', good[:header_end].replace(
            b'element face', b'element vertex 100\nproperty double x\nelement face') +
            good[header_end:]), 'declared twice', None),
        (write_bytes('range.off', b'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n'), 'out of range',
         6),
        (write_bytes('two.off', b'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n'), 'at least 3', 6),
        (write_bytes('short.off', b'OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n'), 'ends at vertex', None),
        (write_bytes('truncated.stl', stl_bytes[:-10]), 'truncated', None),
        (write_bytes('tiny.stl', b'\x00' * 20), 'too short', None),
        (write_bytes('two.stl', b'solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n'
                     b'vertex 1 0 0\nendloop\nendfacet\nendsolid x\n'), 'at least 3', 7),
        (write_bytes('junk.xyz', b'\x01\x02\x03garbage'), 'unknown file format', None),
        (work('bad/missing.obj'), 'cannot open', None),
        (os.path.dirname(work('bad/x')), 'directory', None),
        # Defect 4: only regular files are read (a FIFO blocked in open()
        # forever, /dev/zero grew without bound).
        (make_fifo(work('bad/fifo.obj')), 'regular file', None),
        ('/dev/zero', 'regular file', None),
        ('/dev/urandom', 'regular file', None),
    ]
    for path, message, line in cases:
        for command in ('check', 'info'):
            status, out, err = run(command, path)
            lines = [x for x in err.splitlines() if x.strip()]
            name = os.path.basename(path)
            check(status == 2, '%s %s: exit %d, expected 2 (%s)' % (command, name, status, err))
            check(len(lines) == 1, '%s %s: expected one line on stderr, got %r'
                  % (command, name, err))
            check(path in lines[0], '%s %s: message does not name the file: %r'
                  % (command, name, lines[0]))
            check(re.search(message, lines[0], re.IGNORECASE),
                  '%s %s: message %r does not say %r' % (command, name, lines[0], message))
            if line is not None:
                check('%s:%d:' % (path, line) in lines[0],
                      '%s %s: message %r does not give line %d' % (command, name, lines[0], line))


def test_hostile_input():
    """The hardening issue's defects in the tool, each as it was reported."""
    pos, tris = fx.grid_sheet(3, 3, fx.flat)
    mesh = work('hostile/sheet.obj')
    fx.write_obj(mesh, pos, tris)
    # 1. Field widths overflowed a 128-byte buffer (a segfault): refused
    # above 64 with a usage error, for inputs and outputs alike.
    for args in (['check', '--range', '0:0', work('hostile/f_%0999d.obj')],
                 ['check', mesh, '--mark', work('hostile/out_%0300d.ply')],
                 ['check', mesh, '--png', work('hostile/o_%200d.png')]):
        status, out, err = run(*args)
        check(status == 2, '%s: exit %d, expected 2 (%s)' % (args, status, err))
        check(err.count('\n') >= 1 and 'Segmentation' not in err, '%s: %r' % (args, err))
    status, out, err = run('check', mesh, '--mark', work('hostile/mark_%064d.ply'), expect=0)
    check(os.path.exists(work('hostile/mark_%064d.ply' % 0)), 'a 64-wide pattern is expanded')
    # 3. A UTF-8 byte-order mark hid the first line: the same answer as without.
    with open(mesh, 'rb') as f:
        plain = f.read()
    bom = write_bytes('../hostile/bom.obj', b'\xef\xbb\xbf' + plain)
    _, a = check_json(mesh, '--distance', '0.3', expect=0)
    _, b = check_json(bom, '--distance', '0.3', expect=0)
    check(a[0]['counts'] == b[0]['counts'] and
          a[0]['stats']['vertices'] == b[0]['stats']['vertices'],
          'byte-order mark: %s vs %s' % (b[0]['counts'], a[0]['counts']))
    info = run('info', '--json', '-', bom, expect=0)[1]
    check(json.loads(info.splitlines()[0])['vertices'] == len(pos), 'info with a BOM: %s' % info)
    # 2. One face line repeating the same triangle (and quad) made the
    # hierarchy build quadratic in memory and cubic in time: it now finishes
    # (the build is linear; the query still meets every pair of copies, as
    # their boxes coincide: 2000 copies keep it to a second).
    for name, face in (('tri', b' 1 2 3'), ('quad', b' 1 2 3 4')):
        text = b'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf' + face * 2000 + b'\n'
        path = write_bytes('../hostile/repeat_%s.obj' % name, text)
        status, out, err = run('check', path, '--quiet')
        check(status in (0, 1), 'repeated face %s: exit %d (%s)' % (name, status, err))
    # 8. --distance 1e-320 is a valid number >= 0; --distance-rel 1e308 makes
    # d overflow: a clear message, not "query failed".
    run('check', mesh, '--distance', '1e-320', '--quiet', expect=0)
    status, out, err = run('check', mesh, '--distance-rel', '1e308')
    check(status == 2 and 'distance-rel' in err and 'query failed' not in err,
          '--distance-rel 1e308: exit %d, %r' % (status, err))
    # 9. Output errors: one message of ours (not libpng's too), and a full
    # stdout is an error with a word.
    if os.path.exists('/dev/full'):
        status, out, err = run('check', mesh, '--png', '/dev/full')
        lines = [x for x in err.splitlines() if x.strip()]
        check(status == 2 and len(lines) == 1 and 'PNG' in lines[0],
              '--png /dev/full: exit %d, %r' % (status, err))
        with open('/dev/full', 'w') as full:
            proc = subprocess.run([ARGS.cli, 'check', mesh], stdout=full,
                                  stderr=subprocess.PIPE, timeout=600)
        err = proc.stderr.decode()
        check(proc.returncode == 2 and 'standard output' in err,
              'check > /dev/full: exit %d, %r' % (proc.returncode, err))
        with open('/dev/full', 'w') as full:
            proc = subprocess.run([ARGS.cli, 'info', mesh], stdout=full,
                                  stderr=subprocess.PIPE, timeout=600)
        check(proc.returncode == 2 and 'standard output' in proc.stderr.decode(),
              'info > /dev/full: exit %d' % proc.returncode)
    status, out, err = run('check', mesh, '--png', work('hostile/big.png'), '--size', '8192x8192')
    check(status == 2 and '4096' in err, '--size 8192x8192: exit %d, %r' % (status, err))


def test_messages_name_the_culprit():
    """Hardening 0.4: a coordinate beyond 2^200 (or nonzero below 2^-200)
    was "count or index out of the supported range", and a frame whose
    triangles differ only "topology differs (72 vertices, 100 triangles;
    the first frame has 72 and 100)". Both name what is wrong now."""
    pos, tris = fx.grid_sheet(4, 4, fx.flat)
    for value, says in ((1e300, 'beyond the largest coordinate magnitude 2^200'),
                        (-1e-310, 'below the smallest nonzero coordinate magnitude 2^-200')):
        bad = [list(p) for p in pos]
        bad[7][1] = value
        bad = [tuple(p) for p in bad]
        path = work('culprit/far_%g.obj' % abs(value))
        fx.write_obj(path, bad, tris)
        status, _, err = run('check', path)
        check(status == 2 and 'vertex 7, coordinate y' in err and says in err and path in err,
              '%g: exit %d, %r' % (value, status, err))
        # The same coordinate in a later frame of a sequence.
        first = work('culprit/first.obj')
        fx.write_obj(first, pos, tris)
        status, _, err = run('check', '--frames', first, path)
        check(status == 2 and 'vertex 7, coordinate y' in err and says in err,
              'frames, %g: exit %d, %r' % (value, status, err))
    # Same counts, one triangle turned: the message names it and both versions.
    first = work('culprit/topology_0.obj')
    fx.write_obj(first, pos, tris)
    turned = [list(t) for t in tris]
    k = len(turned) // 2
    turned[k] = [turned[k][0], turned[k][2], turned[k][1]]
    second = work('culprit/topology_1.obj')
    fx.write_obj(second, pos, turned)
    for command in ('check', 'track'):
        frames = ['--frames'] if command == 'check' else []
        status, _, err = run(command, *frames, first, second)
        want = ('triangle %d is (%d %d %d); in the first frame it is (%d %d %d)'
                % ((k,) + tuple(turned[k]) + tuple(tris[k])))
        check(status == 2 and want in err and second in err,
              '%s: exit %d, %r (want %r)' % (command, status, err, want))
    fewer = work('culprit/fewer.obj')
    fx.write_obj(fewer, pos, tris[:-1])
    status, _, err = run('check', '--frames', first, fewer)
    check(status == 2 and '%d triangles; the first frame has %d' % (len(tris) - 1, len(tris))
          in err, 'fewer triangles: exit %d, %r' % (status, err))


def frame_positions(k):
    """Frame k of a sheet closing into a figure eight: k = 0 is open, 2 crosses."""
    def surface(u, v):
        x, y, z = fx.figure_eight(u, v)
        s = 0.5 + 0.25 * k
        return (x * s + (1 - s) * (u - 0.5), y, z * s)
    return fx.grid_sheet(12, 5, surface, jitter=0.004, seed=7)


def test_frames():
    paths = []
    for k in range(3):
        pos, tris = frame_positions(k)
        paths.append(work('frames/frame_%03d.ply' % k))
        fx.write_ply(paths[-1], pos, tris, 'binary_little_endian', 'double')
    pattern = work('frames/frame_%03d.ply')
    singles = []
    for p in paths:
        singles.append(check_json('--distance', '0.01', p)[1][0])
    check(any(s['counts']['ef'] for s in singles) and not all(s['counts']['ef'] for s in singles),
          'the fixture frames should intersect in some frames only')
    want_status = 1 if any(s['counts']['ef'] for s in singles) else 0
    for args in (['--range', '0:2', pattern], ['--frames'] + paths):
        status, objs = check_json('--distance', '0.01', *args)
        check(status == want_status, 'frames %s: exit %d' % (args[0], status))
        check(len(objs) == 3, 'frames %s: %d JSON lines, expected 3' % (args[0], len(objs)))
        for k, (o, s) in enumerate(zip(objs, singles)):
            check(o['frame'] == k, 'frame number %r' % o.get('frame'))
            check(o['files'] == [paths[k]], 'frame %d files %r' % (k, o['files']))
            for key in KEYS:
                check(o[key] == s[key], 'frame %d (refit): %s differs from a fresh check'
                      % (k, key))
    # A sequence that stands still is answered from the coherent query's near
    # list after its first two frames (fresh, then a rebuild): still the
    # fresh check's contacts.
    still = [paths[1]] * 4
    status, objs = check_json('--distance', '0.01', '--frames', *still)
    check(len(objs) == 4, 'still frames: %d JSON lines' % len(objs))
    for k, o in enumerate(objs):
        for key in KEYS:
            check(o[key] == singles[1][key], 'still frame %d: %s differs from a fresh check'
                  % (k, key))
    check(objs[3]['stats']['nodes_visited'] == 0 and objs[0]['stats']['nodes_visited'] > 0,
          'still frames: the last one should come from the near list (no traversal)')
    # The summary names the intersecting frames, runs as FIRST-LAST.
    hit = [k for k, s in enumerate(singles) if s['counts']['ef']]
    runs, start = [], None
    for k in hit:
        if start is None or k != runs[-1][1] + 1:
            runs.append([k, k])
        else:
            runs[-1][1] = k
        start = k
    text = ', '.join('%d-%d' % (a, b) if b > a else '%d' % a for a, b in runs)
    _, out, _ = run('check', '--distance', '0.01', '--range', '0:2', pattern)
    check('frames with interferences: %s\n' % text in out, 'summary %r lacks the frame list %r'
          % (out, text))
    # Every other frame, pictures per frame.
    status, objs = check_json('--distance', '0.01', '--range', '0:2:2', '--png',
                              work('frames/pic_%d.png'), pattern)
    check([o['frame'] for o in objs] == [0, 2], 'range step: frames %r' % [o['frame'] for o in objs])
    check(os.path.exists(work('frames/pic_0.png')) and os.path.exists(work('frames/pic_2.png')),
          'per-frame pictures')
    # A frame with another topology is an input error.
    pos, tris = fx.grid_sheet(5, 5, fx.flat)
    other = work('frames/other.ply')
    fx.write_ply(other, pos, tris)
    status, out, err = run('check', '--frames', paths[0], other)
    check(status == 2 and 'topology' in err and other in err, 'topology change: %d %s'
          % (status, err))
    run('check', '--range', '0:5', pattern, expect=2)  # frame_003.ply is missing


def test_outputs():
    pos, tris = figure_eight_mesh()
    path = work('out/eight.obj')
    fx.write_obj(path, pos, tris)
    png, mark, csv = work('out/eight.png'), work('out/eight_marked.ply'), work('out/eight.csv')
    status, out, err = run('check', '--png', png, '--mark', mark, '--csv', csv, '--view',
                           '10,40', '--size', '320x200', path, expect=1)
    check('EF interferences' in out and 'intersecting triangle pairs' in out, 'summary: %s' % out)
    _, objs = check_json(path)
    o = objs[0]
    # CSV: one row per entry, same indices as the JSON.
    rows = open(csv).read().splitlines()
    check(rows[0] == 'frame,kind,i0,i1,i2,i3,distance', 'csv header %r' % rows[0])
    by_kind = {}
    for row in rows[1:]:
        cells = row.split(',')
        by_kind.setdefault(cells[1], []).append([int(c) for c in cells[2:6] if c])
    for kind, key in (('vf', 'vf'), ('ee', 'ee'), ('ef', 'ef'), ('tt', 'intersecting_triangles')):
        check(by_kind.get(kind, []) == o[key], 'csv %s rows differ from the JSON' % kind)
    # PNG: signature, size, and red pixels for the intersecting triangles.
    data = open(png, 'rb').read()
    check(data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG')
    width, height = struct.unpack('>II', data[16:24])
    check((width, height) == (320, 200), 'PNG size %dx%d' % (width, height))
    idat, pos_ = b'', 8
    while pos_ < len(data):
        n, kind = struct.unpack('>I4s', data[pos_:pos_ + 8])
        if kind == b'IDAT':
            idat += data[pos_ + 8:pos_ + 8 + n]
        pos_ += 12 + n
    raw = zlib.decompress(idat)
    check(len(raw) == height * (1 + 3 * width), 'PNG is not 8-bit RGB')
    # Unfilter rows (filters 0-4) enough to count reddish pixels.
    stride, prev, reds = 3 * width, bytearray(3 * width), 0
    for y in range(height):
        f = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = row[i - 3] if i >= 3 else 0
            b = prev[i]
            c = prev[i - 3] if i >= 3 else 0
            if f == 1:
                row[i] = (row[i] + a) & 255
            elif f == 2:
                row[i] = (row[i] + b) & 255
            elif f == 3:
                row[i] = (row[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        for i in range(0, stride, 3):
            if row[i] > 60 and row[i] > 2 * row[i + 1] and row[i] > 2 * row[i + 2]:
                reds += 1
        prev = row
    check(reds > 0, 'no red (intersecting) pixels in the picture')
    # Marked PLY: loads back, faces coloured red exactly for intersecting triangles.
    _, out, _ = run('info', '--json', '-', mark, expect=0)
    check(json.loads(out)['triangles'] == len(tris), 'marked PLY triangle count')
    lines = open(mark).read().splitlines()
    faces = lines[-len(tris):]
    red = {i for i, f in enumerate(faces) if f.split()[-3:] == ['214', '39', '40']}
    want = {t for pair in o['intersecting_triangles'] for t in pair}
    check(red == want, 'marked PLY: red faces %s, intersecting %s' % (sorted(red)[:5],
                                                                      sorted(want)[:5]))


def test_bundled_ribbon():
    """The bundled mesh of `make run`, against the brute force: it has every
    kind of contact, and every method reports the right ones."""
    ribbon = os.path.join(ARGS.source, 'tests', 'data', 'folded_ribbon.obj')
    mesh = fx.read_simple_obj(ribbon)
    run_against_brute_force([mesh], [ribbon], {}, 'folded ribbon')


def test_progress():
    """A progress bar on stderr only when it is a terminal."""
    import pty
    pos, tris = fx.grid_sheet(150, 150, fx.wavy)  # a 4 MB OBJ: several progress steps
    path = work('progress/sheet.obj')
    fx.write_obj(path, pos, tris)
    status, out, err = run('check', path, expect=0)
    check(err == '', 'stderr is not a terminal, yet it got %r' % err[:200])
    master, slave = pty.openpty()
    proc = subprocess.run([ARGS.cli, 'info', path], stdout=subprocess.DEVNULL, stderr=slave,
                          timeout=600)
    os.close(slave)
    seen = b''
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # the terminal closed
            break
        if not chunk:
            break
        seen += chunk
    os.close(master)
    check(proc.returncode == 0, 'info under a terminal: exit %d' % proc.returncode)
    check(b'%' in seen and b'[' in seen, 'no progress bar on a terminal: %r' % seen[:200])
    _, out, _ = run('check', '--quiet', path, expect=0)
    check(out == '', '--quiet printed %r' % out[:200])


def test_cloth_ball_frames():
    frames = os.path.join(ARGS.shared or '', 'sample-scalable-ccd-data', 'cloth-ball', 'frames')
    files = sorted(glob.glob(os.path.join(frames, '*.ply')) + glob.glob(os.path.join(frames, '*.obj')),
                   key=lambda p: (len(p), p))
    if len(files) < 2:
        print('skipped: no cloth-ball frames under %s' % frames)
        sys.exit(SKIP)
    pair = files[:2]
    status, objs = check_json('--frames', *pair)
    check(status in (0, 1) and len(objs) == 2, 'two frames: exit %d, %d objects'
          % (status, len(objs)))
    # A sequence has one detection distance, the first frame's (a cloth's
    # thickness does not change per frame; docs/cli.md): check each frame
    # afresh at that same distance.
    d = objs[0]['distance']
    check(objs[1]['distance'] == d, 'frames use different distances: %r, %r'
          % (d, objs[1]['distance']))
    for k, path in enumerate(pair):
        _, single = check_json('--distance', repr(d), path)
        for key in KEYS:
            check(objs[k][key] == single[0][key], 'cloth-ball frame %d: %s differs from a fresh '
                  'check' % (k, key))
    print('cloth-ball: %s' % [o['counts'] for o in objs])


# ---------------------------------------------------------------------------
# check --continuous: pairs that touch within the steps between frames.

def test_continuous():
    """spikes_frame: the spike's lowest vertex p (index 3) goes from 0.3 above
    the big triangle T (index 0) to 0.3 below it in the second step, passing
    through T's interior at the step's middle; it touches nothing else (the
    spike's other vertices stay 3 up, T's border is 1 away). The discrete
    check sees frame 2's crossing edges (EF) but not the passage; the
    continuous check finds exactly VF (3, 0) in step 1 -> 2, at a time of
    impact just at or before 0.5."""
    paths, pattern = write_sequence('continuous', [[3, 3], [3, 3], [-3, 3]])
    csv = work('continuous/steps.csv')
    status, out, _ = run('check', '--continuous', '--frames', *paths, '--csv', csv, expect=1)
    check('2 step(s): 1 with colliding pairs' in out, 'summary: %r' % out)
    check('COLLIDES WITHIN A STEP' in out, 'result line: %r' % out)
    rows = open(csv).read().splitlines()
    check(rows[0] == 'step_from,step_to,kind,i0,i1,i2,i3,toi,flags', 'header %r' % rows[0])
    check(len(rows) == 2, 'expected one colliding pair, got %r' % rows[1:])
    f = rows[1].split(',')
    check(f[:7] == ['1', '2', 'VF', '3', '0', '', ''], 'row %r' % rows[1])
    toi = float(f[7])
    check(0.5 - 1e-4 <= toi <= 0.5, 'time of impact %r, expected just at or before 0.5' % toi)
    check(f[8] == '0', 'flags %r' % f[8])
    # The same frames, discretely: nothing near at frames 0 and 1 (0.3 from
    # T, beyond d), frame 2 intersecting.
    _, out, _ = run('check', '--frames', *paths, '--distance', '0.1', expect=1)
    check('frames with interferences: 2\n' in out and '0 with proximities' in out,
          'discrete summary %r' % out)
    # --range works the same way; a step that stays clear: exit 0.
    run('check', '--continuous', '--range', '1:2', pattern, expect=1)
    run('check', '--continuous', '--range', '0:1', pattern, expect=0)
    # --distance 0.35: both spikes' lowest vertices (3 and 6) are 0.3 above
    # T from the start: time 0, flagged initial (flag 1).
    run('check', '--continuous', '--range', '0:1', pattern, '--distance', '0.35',
        '--csv', csv, expect=1)
    rows = open(csv).read().splitlines()
    check(rows[1:] == ['0,1,VF,3,0,,,0,1', '0,1,VF,6,0,,,0,1'], 'initial contact rows %r' % rows)
    # Usage errors: no sequence, or an output it does not write.
    _, _, err = run('check', '--continuous', paths[0], expect=2)
    check('--frames or --range' in err, 'stderr %r' % err)
    _, _, err = run('check', '--continuous', '--frames', *paths, '--mark', work('c.ply'), expect=2)
    check('--mark' in err, 'stderr %r' % err)


def flattened_ribbon(folder):
    """The bundled folded ribbon, and a copy flattened to 0.3 of its height
    (written under work(folder)): one step that passes its fold's layers
    through each other."""
    ribbon = os.path.join(ARGS.source, 'tests', 'data', 'folded_ribbon.obj')
    flat = work(folder + '/flattened.obj')
    with open(ribbon) as src, open(flat, 'w') as dst:
        for line in src:
            if line.startswith('v '):
                x, y, z = map(float, line.split()[1:4])
                line = 'v %r %r %r\n' % (x, y, 0.3 * z)
            dst.write(line)
    return ribbon, flat


def test_continuous_json():
    """check --continuous --json: one object per step, the pairs of the CSV
    with their time of impact and flags, in file indices (the spikes of
    test_continuous)."""
    paths, pattern = write_sequence('continuous_json', [[3, 3], [3, 3], [-3, 3]])
    csv = work('continuous_json/steps.csv')
    status, out, err = run('check', '--continuous', '--frames', *paths, '--csv', csv,
                           '--json', '-', expect=1)
    check('2 step(s): 1 with colliding pairs' in err, 'the summary goes to stderr: %r' % err)
    objs = [json.loads(line) for line in out.splitlines() if line.strip()]
    check(len(objs) == 2, 'expected one object per step, got %d' % len(objs))
    check([o['step'] for o in objs] == [{'from': 0, 'to': 1}, {'from': 1, 'to': 2}],
          'steps %r' % [o['step'] for o in objs])
    check([o['files'] for o in objs] == [paths[0:2], paths[1:3]], 'files %r' % objs[0]['files'])
    for o in objs:
        for key, kind in (('selfcol_version', str), ('separation', (int, float)),
                          ('method', str), ('counts', dict), ('free_fraction', (int, float)),
                          ('vf', list), ('ee', list), ('stats', dict)):
            check(isinstance(o.get(key), kind), 'key %s missing or of the wrong type' % key)
        check(o['method'] == 'bvh' and o['separation'] == 0, 'method %r' % o['method'])
        check(o['counts'] == {'vf': len(o['vf']), 'ee': len(o['ee'])}, 'counts %r' % o['counts'])
        for key in ('vertices', 'triangles', 'edges', 'candidates', 'seconds'):
            check(key in o['stats'], 'stats.%s missing' % key)
    check(objs[0]['vf'] == [] and objs[0]['ee'] == [] and objs[0]['free_fraction'] == 1,
          'first step: %r' % objs[0])
    rows = open(csv).read().splitlines()[1:]
    f = rows[0].split(',')
    check(objs[1]['vf'] == [[3, 0, float(f[7]), 0]] and objs[1]['ee'] == [],
          'second step: %r, CSV %r' % (objs[1]['vf'], rows))
    check(objs[1]['free_fraction'] == float(f[7]), 'free fraction %r' % objs[1]['free_fraction'])
    # Within --distance 0.35 from the start: both lowest vertices at time 0,
    # flag 1 (initial); the exhaustive reference writes the same records.
    objs = {}
    for method in ('bvh', 'exhaustive'):
        _, out, _ = run('check', '--continuous', '--range', '0:1', pattern, '--distance', '0.35',
                        '--method', method, '--quiet', '--json', '-', expect=1)
        objs[method] = json.loads(out)
        check(objs[method]['method'] == method, 'method %r' % objs[method]['method'])
        check(objs[method]['separation'] == 0.35, 'separation %r' % objs[method]['separation'])
    check(objs['bvh']['vf'] == [[3, 0, 0, 1], [6, 0, 0, 1]], 'initial records %r' % objs['bvh'])
    check(objs['bvh']['vf'] == objs['exhaustive']['vf'] and
          objs['bvh']['ee'] == objs['exhaustive']['ee'], 'bvh and exhaustive differ')
    # EE records: the bundled ribbon flattened to 0.3 of its height in one
    # step, so layers of its fold pass through each other (edge-edge pairs):
    # sorted vertex pairs in ascending order, the times of impact of the CSV.
    ribbon, flat = flattened_ribbon('continuous_json')
    _, out, _ = run('check', '--continuous', '--frames', ribbon, flat, '--csv', csv, '--json', '-',
                    expect=1)
    o = json.loads(out)
    rows = [r.split(',') for r in open(csv).read().splitlines()[1:]]
    check(o['counts']['ee'] > 0 and o['counts']['ee'] == sum(r[2] == 'EE' for r in rows) and
          o['counts']['vf'] == sum(r[2] == 'VF' for r in rows), 'counts %r' % o['counts'])
    check(all(a0 < a1 and b0 < b1 and (a0, a1) < (b0, b1) for a0, a1, b0, b1, _, _ in o['ee']),
          'ee edges are not sorted pairs in ascending order')
    check(o['ee'] == sorted(o['ee']), 'ee is not sorted')
    # The CSV's rows are the JSON's records (docs/cli.md): VF rows v, t and
    # EE rows a0, a1, b0, b1 as vertex indices (not the library's edge
    # numbers), in the JSON's order, with the same times and flags.
    csv_vf = [[int(r[3]), int(r[4]), float(r[7]), int(r[8])] for r in rows if r[2] == 'VF']
    csv_ee = [[int(x) for x in r[3:7]] + [float(r[7]), int(r[8])] for r in rows if r[2] == 'EE']
    check(all(r[5] == r[6] == '' for r in rows if r[2] == 'VF'), 'VF rows fill i2 or i3')
    check(csv_vf == o['vf'], 'CSV VF rows %r differ from the JSON %r' % (csv_vf[:3], o['vf'][:3]))
    check(csv_ee == o['ee'], 'CSV EE rows %r differ from the JSON %r' % (csv_ee[:3], o['ee'][:3]))
    # Each EE row names two edges of the mesh, by their vertices.
    edges = set()
    for line in open(flat):
        if line.startswith('f '):
            f = [int(x.split('/')[0]) - 1 for x in line.split()[1:]]
            for i in range(len(f)):
                edges.add(tuple(sorted((f[i], f[(i + 1) % len(f)]))))
    check(all((a0, a1) in edges and (b0, b1) in edges for a0, a1, b0, b1, _, _ in csv_ee),
          'an EE row names a vertex pair that is no edge of the mesh')


def test_continuous_methods():
    """check --continuous --method: bvh (the default, as the continuous
    query's), exact and exhaustive run the continuous query's method of
    that name (include/selfcol/sweep.h); seed and cone have no continuous
    query and are usage errors. On the bundled ribbon flattened in one step
    (as in test_continuous_json): BVH and EXHAUSTIVE report the same pairs;
    EXACT only skips pairs BVH would have examined (fewer or as many
    candidates, its pairs among BVH's); on the spikes it finds the passage
    VF (3, 0) as the others do."""
    ribbon, flat = flattened_ribbon('continuous_methods')
    objs = {}
    for method in (None, 'bvh', 'exact', 'exhaustive'):
        extra = ('--method', method) if method else ()
        _, out, err = run('check', '--continuous', '--frames', ribbon, flat, *extra,
                          '--json', '-', expect=1)
        o = json.loads(out)
        want = method or 'bvh'
        check(o['method'] == want, '--method %s: JSON method %r' % (method, o['method']))
        check('method %s\n' % want in err, '--method %s: summary %r' % (method, err))
        objs[method] = o
    pairs = lambda o: (o['vf'], o['ee'])
    check(pairs(objs[None]) == pairs(objs['bvh']), 'the default is not bvh')
    check(pairs(objs['bvh']) == pairs(objs['exhaustive']), 'bvh and exhaustive differ')
    check(objs['bvh']['counts']['ee'] > 0, 'the ribbon step must collide')
    check(objs['exact']['stats']['candidates'] <= objs['bvh']['stats']['candidates'],
          'exact examined more candidates than bvh: %r' % objs['exact']['stats'])
    check(all(r in objs['bvh']['ee'] for r in objs['exact']['ee']) and
          all(r in objs['bvh']['vf'] for r in objs['exact']['vf']),
          'exact reports a pair that bvh does not')
    paths, _ = write_sequence('continuous_methods', [[3, 3], [3, 3], [-3, 3]])
    for method in ('bvh', 'exact', 'exhaustive'):
        _, out, _ = run('check', '--continuous', '--frames', *paths, '--method', method,
                        '--quiet', '--json', '-', expect=1)
        o = [json.loads(line) for line in out.splitlines() if line.strip()][1]
        check([r[:2] for r in o['vf']] == [[3, 0]] and o['ee'] == [],
              '--method %s: step 1 -> 2 %r' % (method, o))
    for method in ('seed', 'cone'):
        _, _, err = run('check', '--continuous', '--frames', *paths, '--method', method, expect=2)
        check('--continuous has no method %s' % method in err, 'stderr %r' % err)


# ---------------------------------------------------------------------------
# track: sequences through the contact store.

def spikes_frame(heights, d=0.1):
    """One big triangle T in the plane z = 0 (normal +z) and small upright
    triangles ("spikes") whose lowest vertex p_i is at heights[i] times d above
    T's interior, the rest of each spike 3 units higher. A spike at 0.5
    touches T (one VF contact, no EE: every other element is far away); at
    -0.5 its vertex has gone through T (the same VF contact on the other
    side, and its two edges from p_i cross T: 2 EF interferences); at 3 it
    is clear of T."""
    pos = [(0.0, 0.0, 0.0), (4.0, 0.0, 0.0), (0.0, 4.0, 0.0)]
    tris = [(0, 1, 2)]
    for i, h in enumerate(heights):
        x, y = ((1.0, 1.0), (2.5, 0.5))[i]
        base = len(pos)
        pos += [(x, y, h * d), (x + 0.5, y, 3.0), (x, y + 0.5, 3.0)]
        tris.append((base, base + 1, base + 2))
    return pos, tris


def write_sequence(name, heights_per_frame):
    """Frames name_000.obj ... of spikes_frame(); returns (paths, pattern)."""
    paths = []
    for k, heights in enumerate(heights_per_frame):
        pos, tris = spikes_frame(heights)
        paths.append(work('track/%s_%03d.obj' % (name, k)))
        fx.write_obj(paths[-1], pos, tris)
    return paths, work('track/%s_%%03d.obj' % name)


def track_jsonl(*args, expect=None):
    """Runs track with --jsonl - and returns (status, objects, stderr)."""
    status, out, err = run('track', '--jsonl', '-', *args, expect=expect)
    return status, [json.loads(line) for line in out.splitlines() if line.strip()], err


TRACK_KEYS = ('frame', 'file', 'contacts', 'regions', 'new', 'kept', 'remnant', 'dropped',
              'flipped', 'corrected', 'corrected_regions', 'interferences', 'crossed_regions')


def check_track_object(o, what):
    for key in TRACK_KEYS[2:]:
        check(isinstance(o.get(key), int) and o[key] >= 0, '%s: %s is not a count: %r'
              % (what, key, o.get(key)))
    check(isinstance(o['frame'], int) and isinstance(o['file'], str), '%s: frame, file' % what)
    for key in ('query_ms', 'store_ms'):
        check(isinstance(o.get(key), (int, float)), '%s: %s missing' % (what, key))
    det = o['detected']
    check(o['kept'] + o['new'] == det['vf'] + det['ee'], '%s: kept + new = %d, detected %s'
          % (what, o['kept'] + o['new'], det))
    check(o['contacts'] == o['kept'] + o['new'] + o['remnant'],
          '%s: contacts %d != kept + new + remnant' % (what, o['contacts']))
    check(o['interferences'] == det['ef'], '%s: interferences %d, detected %d EF'
          % (what, o['interferences'], det['ef']))


def test_track_flip():
    """A vertex goes through a triangle: flipped 1 on the crossing frame."""
    paths, pattern = write_sequence('flip', [[30], [0.5], [-0.5]])
    status, objs, err = track_jsonl('--distance', '0.1', *paths)
    check(status == 1, 'crossing sequence: exit %d (%s)' % (status, err))
    check(len(objs) == 3, '%d JSON lines, expected 3' % len(objs))
    for k, o in enumerate(objs):
        check_track_object(o, 'frame %d' % k)
        check(o['frame'] == k and o['file'] == paths[k], 'frame %d: frame %r, file %r'
              % (k, o['frame'], o['file']))
    want = [dict(contacts=0, new=0, flipped=0, interferences=0, regions=0),
            dict(contacts=1, new=1, flipped=0, interferences=0, regions=1, crossed_regions=0),
            dict(contacts=1, new=0, kept=1, flipped=1, interferences=2, corrected=0, regions=1,
                 crossed_regions=1)]
    for k, (o, w) in enumerate(zip(objs, want)):
        for key, value in w.items():
            check(o[key] == value, 'frame %d: %s = %r, expected %r' % (k, key, o[key], value))
    # The human lines went to standard error (standard output holds the JSON).
    check('flipped 1' in err and 'frame 2 (%s)' % paths[2] in err,
          'per-frame lines on stderr: %r' % err)
    # --range gives the same objects, numbered by the range.
    _, ranged, _ = track_jsonl('--distance', '0.1', '--range', '0:2', pattern)
    check([o['flipped'] for o in ranged] == [0, 0, 1] and [o['frame'] for o in ranged] == [0, 1, 2],
          '--range: %s' % ranged)
    # Human output on stdout without --jsonl -, JSON in a file.
    jsonl = work('track/flip.jsonl')
    status, out, err = run('track', '--distance', '0.1', '--jsonl', jsonl, *paths, expect=1)
    lines = [x for x in out.splitlines() if x.startswith('  frame ')]
    check(len(lines) == 3 and 'flipped 1' in lines[2] and 'interferences 2' in lines[2],
          'per-frame lines: %r' % out)
    for word in ('contacts', 'regions', 'new', 'remnant', 'corrected', 'crossed regions', 'query',
                 'store', 'ms'):
        check(word in lines[2], 'the frame line lacks %r: %r' % (word, lines[2]))
    check([json.loads(x) for x in open(jsonl).read().splitlines()][2]['flipped'] == 1,
          '--jsonl FILE')
    # Consistency off: the same crossing is tracked the same way.
    _, objs, _ = track_jsonl('--distance', '0.1', '--no-consistency', *paths)
    check(objs[2]['flipped'] == 1 and objs[2]['corrected'] == 0, '--no-consistency: %s' % objs[2])
    _, out, _ = run('track', '--quiet', '--distance', '0.1', *paths, expect=1)
    check(out == '', '--quiet printed %r' % out)


def test_track_remnance():
    """A contact parts after frame 0: it stays exactly --remnance updates."""
    frames = [[0.5]] + [[30]] * 6
    paths, pattern = write_sequence('part', frames)
    for remnance in (None, 0, 1, 2, 5):
        args = ['--distance', '0.1', '--range', '0:%d' % (len(frames) - 1), pattern]
        if remnance is not None:
            args = ['--remnance', str(remnance)] + args
        r = 4 if remnance is None else remnance  # SELFCOL_STORE_DEFAULT_REMNANCE
        status, objs, err = track_jsonl(*args, expect=0)
        check(len(objs) == len(frames), 'remnance %s: %d objects' % (remnance, len(objs)))
        for k, o in enumerate(objs):
            check_track_object(o, 'remnance %s, frame %d' % (remnance, k))
            held = 1 if k <= r else 0
            check(o['contacts'] == held, 'remnance %s, frame %d: contacts %d, expected %d'
                  % (remnance, k, o['contacts'], held))
            want_remnant = 1 if 1 <= k <= r else 0
            check(o['remnant'] == want_remnant, 'remnance %s, frame %d: remnant %d, expected %d'
                  % (remnance, k, o['remnant'], want_remnant))
            check(o['dropped'] == (1 if k == r + 1 else 0), 'remnance %s, frame %d: dropped %d'
                  % (remnance, k, o['dropped']))
            check(o['new'] == (1 if k == 0 else 0) and o['interferences'] == 0,
                  'remnance %s, frame %d: %s' % (remnance, k, o))


def test_track_summary():
    """Intersecting frames 1-2 and 4, the worst (two spikes through) 2."""
    d = 0.5
    frames = [[6, 6], [-d, 6], [-d, -d], [6, 6], [-d, 6]]
    paths, pattern = write_sequence('summary', frames)
    status, out, err = run('track', '--distance', '0.1', '--range', '0:4', pattern)
    check(status == 1, 'exit %d, expected 1 (%s)' % (status, err))
    check('frames with interferences: 1-2, 4\n' in out, 'frame list: %r' % out)
    check('5 frame(s): 3 with interferences' in out, 'frame count: %r' % out)
    check(re.search(r'worst frame: 2 \(%s\), 4 interferences' % re.escape(paths[2]), out),
          'worst frame: %r' % out)
    check('INTERSECTS' in out, 'result: %r' % out)
    _, objs, _ = track_jsonl('--distance', '0.1', '--range', '0:4', pattern, expect=1)
    check([o['interferences'] for o in objs] == [0, 2, 4, 0, 2],
          'interferences %r' % [o['interferences'] for o in objs])
    # Each frame's interferences are what check finds in it.
    _, checked = check_json('--distance', '0.1', '--range', '0:4', pattern, expect=1)
    check([o['counts']['ef'] for o in checked] == [o['interferences'] for o in objs],
          'track and check disagree on the interferences')
    # A clean sequence exits 0 and lists nothing.
    status, out, err = run('track', '--distance', '0.1', paths[0], paths[3], expect=0)
    check('frames with interferences' not in out and 'worst frame' not in out and
          'result: clean' in out, 'clean sequence: %r' % out)
    # Pictures: --png-worst draws frame 2, --png every frame.
    worst = work('track/worst.png')
    if os.path.exists(worst):
        os.remove(worst)
    run('track', '--distance', '0.1', '--size', '64x48', '--png-worst', worst, '--range', '0:4',
        pattern, expect=1)
    data = open(worst, 'rb').read()
    check(data[:8] == b'\x89PNG\r\n\x1a\n' and struct.unpack('>II', data[16:24]) == (64, 48),
          '--png-worst did not write a 64x48 PNG')
    run('track', '--distance', '0.1', '--size', '64x48', '--png-worst',
        work('track/worst_%d.png'), '--png', work('track/each_%02d.png'), '--range', '0:4',
        pattern, expect=1)
    check(os.path.exists(work('track/worst_2.png')), '--png-worst with %d: not named by frame 2')
    check(all(os.path.exists(work('track/each_%02d.png' % k)) for k in range(5)),
          '--png PATTERN: not every frame drawn')
    # The worst frame's picture is that frame's, not the last one's: it is
    # the picture --png drew of frame 2.
    check(open(work('track/worst_2.png'), 'rb').read() == open(work('track/each_02.png'),
                                                                 'rb').read(),
          '--png-worst is not the picture of the worst frame')


def test_track_errors():
    paths, pattern = write_sequence('err', [[3], [0.5]])
    # Another vertex and triangle count: an input error naming the frame.
    pos, tris = fx.grid_sheet(3, 3, fx.flat)
    other = work('track/other.obj')
    fx.write_obj(other, pos, tris)
    status, out, err = run('track', paths[0], other, paths[1])
    check(status == 2 and 'topology' in err and other in err, 'topology change: %d %r'
          % (status, err))
    # The same counts, other triangles: an input error too.
    pos, tris = spikes_frame([0.5])
    swapped = work('track/swapped.obj')
    fx.write_obj(swapped, pos, [tris[0], tuple(reversed(tris[1]))])
    status, out, err = run('track', paths[0], swapped)
    check(status == 2 and 'topology' in err and swapped in err, 'other triangles: %d %r'
          % (status, err))
    run('track', '--range', '0:5', pattern, expect=2)  # err_002.obj is missing
    status, out, err = run('track', '--range', '0:1', paths[0])  # not a pattern
    check(status == 2 and '--range' in err, '--range without a pattern: %d %r' % (status, err))
    usage = [['track'], ['track', '--remnance', '-1', paths[0]],
             ['track', '--remnance', 'four', paths[0]], ['track', '--remnance', '', paths[0]],
             ['track', '--remnance', '99999999999', paths[0]],
             ['track', '--no-consistency=1', paths[0]], ['track', '--json', '-', paths[0]],
             ['track', '--csv', '-', paths[0]], ['track', '--fail-on', 'proximity', paths[0]],
             ['track', '--distance', '1', '--distance-rel', '0.1', paths[0]],
             ['track', '--method', 'fast', paths[0]], ['track', '--bogus', paths[0]],
             ['track', '--png-worst', work('track/w_%d_%d.png'), paths[0]],
             ['track', paths[0], '--jsonl'],
             ['check', '--jsonl', '-', paths[0]], ['check', '--remnance', '2', paths[0]],
             ['info', '--png-worst', 'x.png', paths[0]]]
    for args in usage:
        status, out, err = run(*args)
        check(status == 2, '%s: exit %d, expected 2' % (args, status))
        check(err.strip() != '' and 'selfcol-cli' in err, '%s: no message on stderr' % args)
        check('--help' in err, '%s: the usage error does not point to --help: %r' % (args, err))
    _, out, _ = run('track', '--help', expect=0)
    for option in ('--distance', '--distance-rel', '--method', '--remnance', '--no-consistency',
                   '--jsonl', '--png', '--png-worst', '--range', '--quiet'):
        check(option in out, 'track --help does not mention %s' % option)
    _, out, _ = run('--help', expect=0)
    check('track' in out, 'the main help does not list track')


# ---------------------------------------------------------------------------
# Hardening 0.3, item 12: the arguments and outputs of track (and check,
# which shares their parsing), each defect as it was reported.

def test_track_unknown_last():
    """1. An unknown option given last was reported as needing a value."""
    paths, _ = write_sequence('unknown', [[3]])
    for cmd in ('track', 'check'):
        status, out, err = run(cmd, paths[0], '--bogus')
        check(status == 2 and "unknown option '--bogus'" in err and 'needs a value' not in err,
              '%s MESH --bogus: exit %d, %r' % (cmd, status, err))
        check('--help' in err, '%s: no pointer to --help: %r' % (cmd, err))
        status, out, err = run(cmd, paths[0], '--bogus=1')
        check(status == 2 and "unknown option '--bogus'" in err, '--bogus=1: %r' % err)
    # An option of another command, last: named as such, not "needs a value".
    for cmd, option, owner in (('track', '--csv', 'check'), ('check', '--jsonl', 'track'),
                               ('track', '--fail-on', 'check')):
        status, out, err = run(cmd, paths[0], option)
        check(status == 2 and 'belongs to the %s command' % owner in err,
              '%s MESH %s: exit %d, %r' % (cmd, option, status, err))
    # A known option without its value still needs one.
    status, out, err = run('track', paths[0], '--jsonl')
    check(status == 2 and "'--jsonl' needs a value" in err, 'track MESH --jsonl: %r' % err)


def test_track_range_limits():
    """2. --range values beyond +-1e9 were reported as "FIRST <= LAST"; the
    limits (+-1e9, at most 1e6 frames) were not documented."""
    _, pattern = write_sequence('limits', [[3], [3]])
    for cmd in ('track', 'check'):
        for value in ('0:99999999999', '-2000000000:0', '0:1000000001', '-1000000001:5',
                      '0:99999999999999999999999', '-99999999999999999999999:0'):
            status, out, err = run(cmd, '--range', value, pattern)
            check(status == 2 and 'out of range' in err and 'FIRST <= LAST' not in err,
                  '%s --range %s: exit %d, %r' % (cmd, value, status, err))
            check('1000000000' in err, '%s --range %s: the limit is not named: %r'
                  % (cmd, value, err))
        status, out, err = run(cmd, '--range', '0:1:99999999999999999999999', pattern)
        check(status == 2 and 'STEP' in err and 'out of range' in err, 'huge STEP: %r' % err)
        # Too many frames names the limit.
        status, out, err = run(cmd, '--range', '0:1000000', pattern)
        check(status == 2 and 'too many frames' in err and '1000000' in err,
              '%s --range 0:1000000: %r' % (cmd, err))
        # What the limits allow passes the range checks (the files are missing).
        for value in ('-1000000000:-1000000000', '1000000000:1000000000', '5:1000004',
                      '-1000000000:1000000000:2000000000'):
            status, out, err = run(cmd, '--range', value, pattern)
            check(status == 2 and '--range' not in err and 'cannot open' in err,
                  '%s --range %s: refused as a range: %r' % (cmd, value, err))
        # The other errors keep their words.
        status, out, err = run(cmd, '--range', '3:1', pattern)
        check(status == 2 and 'FIRST <= LAST' in err, '--range 3:1: %r' % err)
        status, out, err = run(cmd, '--range', '1:3:0', pattern)
        check(status == 2 and 'STEP > 0' in err, '--range 1:3:0: %r' % err)
        run(cmd, '--distance', '0.1', '--range', '0:1', pattern, '--quiet', expect=0)
        # Documented in --help.
        _, out, _ = run(cmd, '--help', expect=0)
        check('1000000000' in out and '1000000 frames' in out,
              '%s --help does not give the --range limits' % cmd)
    doc = open(os.path.join(ARGS.source, 'docs', 'cli.md')).read()
    check('±1000000000' in doc and '1000000 (1e6) frames' in doc,
          'docs/cli.md does not give the --range limits')


def test_numeric_whitespace():
    """3. A trailing space in a number was refused where a leading one was
    accepted: now both are refused, for every numeric option of every command."""
    paths, pattern = write_sequence('spaces', [[3], [0.5]])
    mesh = paths[0]
    picture = work('track/spaces.png')
    cases = [('--distance', '0.1'), ('--distance-rel', '0.2'), ('--view', '10,20'),
             ('--size', '64x48'), ('--range', '0:1')]
    for cmd in ('check', 'track'):
        for option, value in cases + ([('--remnance', '2')] if cmd == 'track' else []):
            inputs = [pattern] if option == '--range' else [mesh]
            extra = ['--png', picture] if option in ('--view', '--size') else []
            # Without spaces: accepted (as --opt VALUE and --opt=VALUE).
            for args in ([option, value], ['%s=%s' % (option, value)]):
                status, out, err = run(cmd, '--quiet', *(args + extra + inputs))
                check(status in (0, 1), '%s %s: exit %d, %r' % (cmd, args, status, err))
            # With a space before, after or inside: refused alike.
            spaced = [' ' + value, value + ' ', '\t' + value, value + '\n']
            if ',' in value or 'x' in value or ':' in value:
                sep = ',' if ',' in value else 'x' if 'x' in value else ':'
                spaced.append(value.replace(sep, sep + ' '))
            for bad in spaced:
                for args in ([option, bad], ['%s=%s' % (option, bad)]):
                    status, out, err = run(cmd, '--quiet', *(args + extra + inputs))
                    check(status == 2 and option in err and 'spaces' in err,
                          '%s %r: exit %d, %r' % (cmd, args, status, err))
    for cmd in ('check', 'track'):
        _, out, _ = run(cmd, '--help', expect=0)
        check('without spaces' in out, '%s --help does not say numbers take no spaces' % cmd)
    doc = open(os.path.join(ARGS.source, 'docs', 'cli.md')).read()
    check('without white space' in doc, 'docs/cli.md does not say numbers take no spaces')


def test_track_same_output():
    """4. --jsonl out.txt --png-worst out.txt wrote one over the other and
    exited 0: outputs naming one file (or an input) are a usage error, before
    any frame is read and before anything is written."""
    paths, pattern = write_sequence('same', [[3], [-0.5], [3]])
    base = work('track/same_out')
    os.makedirs(base, exist_ok=True)
    for name in os.listdir(base):
        os.remove(os.path.join(base, name))
    out_txt = os.path.join(base, 'out.txt')
    dotted = os.path.join(base, '.', 'out.txt')
    existing = os.path.join(base, 'existing.txt')
    with open(existing, 'w') as f:
        f.write('keep\n')
    linked = os.path.join(base, 'linked.txt')
    os.link(existing, linked)
    symlinked = os.path.join(base, 'symlinked.txt')
    os.symlink(existing, symlinked)
    frames = ['--distance', '0.1', '--range', '0:2', pattern]
    clashes = [
        ('track', ['--jsonl', out_txt, '--png-worst', out_txt]),
        ('track', ['--jsonl', out_txt, '--png-worst', dotted]),
        ('track', ['--jsonl', out_txt, '--png', out_txt]),
        ('track', ['--png', out_txt, '--png-worst', out_txt]),
        ('track', ['--png', os.path.join(base, 'f_%d.png'),
                   '--png-worst', os.path.join(base, 'f_2.png')]),
        ('track', ['--png', os.path.join(base, 'g_%d.png'),
                   '--png-worst', os.path.join(base, 'g_%d.png')]),
        ('track', ['--jsonl', existing, '--png-worst', linked]),
        ('track', ['--jsonl', existing, '--png-worst', symlinked]),
        ('check', ['--json', out_txt, '--csv', out_txt]),
        ('check', ['--json', out_txt, '--png', dotted]),
        ('check', ['--mark', out_txt, '--png', out_txt]),
        ('check', ['--csv', existing, '--mark', linked]),
        ('check', ['--png', os.path.join(base, 'f_%d.png'),
                   '--mark', os.path.join(base, 'f_1.png')]),
    ]
    for cmd, outputs in clashes:
        status, out, err = run(cmd, *(outputs + frames))
        check(status == 2 and 'same file' in err and '--help' in err,
              '%s %s: exit %d, %r' % (cmd, outputs, status, err))
        check('frame 0' not in out + err, '%s %s: frames were processed: %r' % (cmd, outputs, out))
        check(not os.path.exists(out_txt) and open(existing).read() == 'keep\n' and
              not any(n.endswith('.png') for n in os.listdir(base)),
              '%s %s: something was written: %s' % (cmd, outputs, os.listdir(base)))
    # An output naming an input (a frame) would destroy it.
    saved = open(paths[1], 'rb').read()
    for cmd, outputs in (('track', ['--png-worst', paths[1]]),
                         ('track', ['--png', work('track/same_%03d.obj')]),
                         ('track', ['--jsonl', paths[2]]), ('check', ['--json', paths[1]]),
                         ('check', ['--mark', work('track/same_%03d.obj')])):
        status, out, err = run(cmd, *(outputs + frames))
        check(status == 2 and 'input' in err, '%s %s: exit %d, %r' % (cmd, outputs, status, err))
        check(open(paths[1], 'rb').read() == saved, '%s %s: a frame was overwritten'
              % (cmd, outputs))
    status, out, err = run('check', paths[0], '--png', paths[0])
    check(status == 2 and 'input' in err, 'check MESH --png MESH: exit %d, %r' % (status, err))
    status, out, err = run('info', '--json', paths[0], paths[0])
    check(status == 2 and 'input' in err, 'info --json MESH MESH: exit %d, %r' % (status, err))
    # --jsonl - and a file standard output is redirected to.
    with open(out_txt, 'w') as f:
        proc = subprocess.run([ARGS.cli, 'track', '--jsonl', '-', '--png-worst', out_txt] + frames,
                              stdout=f, stderr=subprocess.PIPE, timeout=600)
    err = proc.stderr.decode()
    check(proc.returncode == 2 and 'standard output' in err, 'track --jsonl - > FILE '
          '--png-worst FILE: exit %d, %r' % (proc.returncode, err))
    os.remove(out_txt)
    # Different files, and devices, are fine.
    run('track', '--jsonl', out_txt, '--png-worst', os.path.join(base, 'w.png'), '--png',
        os.path.join(base, 'f_%d.png'), '--size', '32x32', *frames, expect=1)
    run('track', '--jsonl', os.devnull, '--png-worst', os.devnull, '--size', '32x32', *frames,
        expect=1)
    run('check', '--json', os.devnull, '--csv', os.devnull, *frames, expect=1)


def test_track_unwritable_early():
    """5. An unwritable --png-worst was found only after every frame: every
    output is checked before the first frame."""
    paths, pattern = write_sequence('early', [[3], [-0.5]])
    # The second frame has another topology: a run that reads frames stops
    # there; the output check must come first.
    pos, tris = fx.grid_sheet(3, 3, fx.flat)
    other = work('track/early_other.obj')
    fx.write_obj(other, pos, tris)
    missing = os.path.join(ARGS.work, 'track', 'no_such_dir', 'sub', 'worst.png')
    shutil.rmtree(os.path.dirname(os.path.dirname(missing)), ignore_errors=True)
    for cmd, option, extra in (('track', '--png-worst', []), ('track', '--png', []),
                               ('track', '--jsonl', []), ('check', '--png', ['--frames']),
                               ('check', '--mark', ['--frames']), ('check', '--json', ['--frames']),
                               ('check', '--csv', ['--frames'])):
        status, out, err = run(cmd, *(extra + [option, missing, paths[0], other]))
        check(status == 2 and option in err and 'no_such_dir' in err and 'topology' not in err,
              '%s %s MISSING/x: exit %d, %r' % (cmd, option, status, err))
        check('frame 0' not in out and out == '', '%s %s: frames were processed first: %r'
              % (cmd, option, out))
    # A directory, and a path through a regular file, are found early too.
    for target in (work('track'), os.path.join(paths[0], 'x.png')):
        status, out, err = run('track', '--png-worst', target, paths[0], other)
        check(status == 2 and 'cannot write' in err and 'topology' not in err,
              '--png-worst %s: exit %d, %r' % (target, status, err))
    # Nothing was started: --jsonl is not created when --png-worst fails.
    jsonl = work('track/early.jsonl')
    if os.path.exists(jsonl):
        os.remove(jsonl)
    status, out, err = run('track', '--jsonl', jsonl, '--png-worst', missing, *paths)
    check(status == 2 and not os.path.exists(jsonl), '--jsonl written before the check: %r' % err)


def test_track_png_stdout():
    """6. --png - wrote a file named '-': refused for pictures and marked
    meshes ('-' is standard output for JSON and CSV only)."""
    paths, pattern = write_sequence('dash', [[3], [-0.5]])
    cwd = work('track/dash_cwd')
    os.makedirs(cwd, exist_ok=True)
    dash = os.path.join(cwd, '-')
    for cmd, option in (('track', '--png'), ('track', '--png-worst'), ('check', '--png'),
                        ('check', '--mark')):
        for args in ([option, '-'], ['%s=-' % option]):
            if os.path.exists(dash):
                os.remove(dash)
            proc = subprocess.run([ARGS.cli, cmd, '--distance', '0.1'] + args + paths[:1],
                                  cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  timeout=600)
            err = proc.stderr.decode()
            check(proc.returncode == 2 and option in err and 'standard output' in err and
                  '--help' in err, '%s %s: exit %d, %r' % (cmd, args, proc.returncode, err))
            check(not os.path.exists(dash), '%s %s wrote a file named -' % (cmd, args))
            check(proc.stdout == b'', '%s %s wrote to standard output' % (cmd, args))
    # ./- is a file named '-', on purpose.
    proc = subprocess.run([ARGS.cli, 'track', '--distance', '0.1', '--size', '32x32',
                           '--png-worst', './-'] + paths, cwd=cwd, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, timeout=600)
    check(proc.returncode == 1 and open(dash, 'rb').read()[:8] == b'\x89PNG\r\n\x1a\n',
          '--png-worst ./-: exit %d, %r' % (proc.returncode, proc.stderr))
    os.remove(dash)
    for cmd in ('check', 'track'):
        _, out, _ = run(cmd, '--help', expect=0)
        check("'-' is refused" in out, '%s --help does not say --png - is refused' % cmd)


def test_track_cloth_ball():
    """The store on two real frames: consistent counters, and the
    interferences check finds."""
    frames = os.path.join(ARGS.shared or '', 'sample-scalable-ccd-data', 'cloth-ball', 'frames')
    pair = [os.path.join(frames, 'cloth_ball%d.ply' % k) for k in (92, 93)]
    if not all(os.path.exists(p) for p in pair):
        print('skipped: no cloth-ball frames 92 and 93 under %s' % frames)
        sys.exit(SKIP)
    status, objs, err = track_jsonl(*pair)
    check(status in (0, 1) and len(objs) == 2, 'exit %d, %d objects (%s)'
          % (status, len(objs), err))
    for k, o in enumerate(objs):
        check_track_object(o, 'cloth-ball frame %d' % k)
    first, second = objs
    check(first['new'] == first['contacts'] and first['kept'] == first['remnant'] == 0 and
          first['flipped'] == 0, 'first frame: everything is new: %s' % first)
    check(second['kept'] + second['new'] + second['remnant'] == second['contacts'],
          'second frame: kept + new + remnant != contacts: %s' % second)
    check(second['kept'] <= first['contacts'], 'second frame keeps more than the first held')
    # The same query as check: its counts, frame by frame (same distance).
    _, checked = check_json('--frames', *pair)
    for k, (o, c) in enumerate(zip(objs, checked)):
        check(o['distance'] == c['distance'], 'frame %d: distance %r, check %r'
              % (k, o['distance'], c['distance']))
        check(o['interferences'] == c['counts']['ef'], 'frame %d: interferences %d, check %d'
              % (k, o['interferences'], c['counts']['ef']))
        check(o['detected']['vf'] == c['counts']['vf'] and
              o['detected']['ee'] == c['counts']['ee'], 'frame %d: detected %s, check %s'
              % (k, o['detected'], c['counts']))
    check(status == (1 if any(o['interferences'] for o in objs) else 0), 'exit status %d' % status)
    print('cloth-ball track: %s' % [{k: o[k] for k in TRACK_KEYS[2:]} for o in objs])


# ---------------------------------------------------------------------------
# --threads: the query's thread count. The library's contract is that the
# contacts and statistics other than times are the same for every count, so
# everything the tool prints must be too, once the times are taken out.

THREAD_COUNTS = ('1', '2', '4')


def without_times(text):
    """text with every wall time taken out: check's 'time:' line and JSON
    "seconds" object, track's '; query .. ms, store .. ms' and query_ms,
    store_ms. Each pattern must have matched where times are printed, so an
    output that changed shape is not compared with its times in it."""
    lines = [x for x in text.split('\n') if not x.startswith('  time: ')]
    text = '\n'.join(lines)
    text = re.sub(r'"seconds":\{[^{}]*\}', '"seconds":{}', text)
    text = re.sub(r'; query [0-9.]+ ms, store [0-9.]+ ms$', '; query - ms, store - ms', text,
                  flags=re.M)
    return re.sub(r'"(query_ms|store_ms)":[-+0-9.eE]+', r'"\1":0', text)


def same_for_every_count(args, what, files=()):
    """Runs args with each --threads count (and without the option, the
    default 1); stdout, stderr and the files written must agree, times
    aside. Returns the exit status and stdout of --threads 1."""
    results = []
    for count in (None,) + THREAD_COUNTS:
        for f in files:
            if os.path.exists(f):
                os.remove(f)
        extra = [] if count is None else ['--threads', count]
        status, out, err = run(*(args[:1] + extra + args[1:]))
        check(status in (0, 1), '%s --threads %s: exit %d, %r' % (what, count, status, err))
        written = []
        for f in files:
            check(os.path.exists(f), '%s --threads %s: %s not written' % (what, count, f))
            written.append(open(f, 'rb').read())
        results.append((count, status, without_times(out), without_times(err), written))
    base = results[1]
    for count, status, out, err, written in results:
        check(status == base[1], '%s: exit %d with --threads %s, %d with 1'
              % (what, status, count, base[1]))
        check(out == base[2], '%s: standard output with --threads %s differs from 1:\n%s\n---\n%s'
              % (what, count, out[:1500], base[2][:1500]))
        check(err == base[3], '%s: standard error with --threads %s differs from 1:\n%s\n---\n%s'
              % (what, count, err[:1500], base[3][:1500]))
        for f, a, b in zip(files, written, base[4]):
            check(a == b, '%s: %s with --threads %s differs from 1' % (what, f, count))
    return base[1], base[2]


def thread_frames(name, count=3, size=(64, 20)):
    """count frames of a 64x20 sheet (2560 triangles) closing into a figure
    eight; frames 1 and 2 cross. Returns (paths, pattern, meshes). Large
    enough that, at --distance 0.01, every method but exhaustive hands the
    traversal to worker threads with --threads 2 and 4 (seen with strace -f
    when the test was written); on smaller meshes the main thread may finish
    the traversal while dividing it up, and no worker would run."""
    paths, meshes = [], []
    for k in range(count):
        def surface(u, v, k=k):
            x, y, z = fx.figure_eight(u, v)
            s = 0.5 + 0.25 * k
            return (x * s + (1 - s) * (u - 0.5), y, z * s)
        meshes.append(fx.grid_sheet(size[0], size[1], surface, jitter=0.002, seed=11))
        paths.append(work('threads/%s_%03d.ply' % (name, k)))
        fx.write_ply(paths[-1], meshes[-1][0], meshes[-1][1], 'binary_little_endian', 'double')
    return paths, work('threads/%s_%%03d.ply' % name), meshes


def test_threads_identical():
    """check and track print the same, times aside, for --threads 1, 2, 4."""
    ribbon = os.path.join(ARGS.source, 'tests', 'data', 'folded_ribbon.obj')
    paths, pattern, meshes = thread_frames('seq')
    sheet = paths[2]
    # A copy of the crossing frame shifted by half an edge: crosses and nears
    # it everywhere, so the query between two meshes has contacts too.
    pos, tris = meshes[2]
    shifted = work('threads/shifted.obj')
    fx.write_obj(shifted, [(x + 0.013, y + 0.007, z + 0.004) for x, y, z in pos], tris)
    csv = work('threads/out.csv')
    mark = work('threads/out.ply')
    png = work('threads/out.png')
    # One mesh, every method, summary and JSON. The exhaustive method runs on
    # one thread whatever the count: it is only held to that on the small
    # ribbon (on the sheets it would take most of the test's time).
    for method in METHODS:
        for mesh, distance in ((ribbon, []), (sheet, ['--distance', '0.01'])):
            if method == 'exhaustive' and mesh == sheet:
                continue
            args = ['--method', method] + distance + [mesh]
            what = 'check %s' % ' '.join(args[:-1] + [os.path.basename(mesh)])
            status, out = same_for_every_count(['check'] + args, what)
            check(status == 1 and 'EF interferences' in out, '%s: %d %r' % (what, status, out))
            status, out = same_for_every_count(['check', '--json', '-'] + args, what + ' --json')
            obj = json.loads(out)
            check(obj['counts']['ef'] > 0 and obj['counts']['vf'] + obj['counts']['ee'] > 0,
                  '%s: the fixture should have contacts: %s' % (what, obj['counts']))
            # The times were where without_times() looks for them.
            check(obj['stats']['seconds'] == {}, '%s: "seconds" left in %s' % (what, obj['stats']))
    # Two meshes (self queries and the query between them), CSV and the
    # marked mesh and picture, in a file each.
    two = ['--distance', '0.01', sheet, shifted]
    status, out = same_for_every_count(
        ['check', '--csv', csv, '--mark', mark, '--png', png, '--size', '64x48'] + two,
        'check MESH MESH2', files=(csv, mark, png))
    check(status == 1, 'check MESH MESH2: exit %d' % status)
    status, out = same_for_every_count(['check', '--json', '-'] + two, 'check MESH MESH2 --json')
    check(json.loads(out)['counts']['ef'] > 0, 'two meshes: no interference')
    # Frame sequences: --frames and --range, summary, JSON Lines and CSV.
    for frames in (['--frames'] + paths, ['--range', '0:2', pattern]):
        what = 'check %s' % frames[0]
        status, out = same_for_every_count(['check', '--distance', '0.01'] + frames, what)
        check(status == 1 and 'frames with interferences: 1-2' in out, '%s: %r' % (what, out))
        status, out = same_for_every_count(['check', '--distance', '0.01', '--json', '-', '--csv',
                                            csv] + frames, what + ' --json', files=(csv,))
        objs = [json.loads(x) for x in out.splitlines()]
        check(len(objs) == 3 and all(o['counts']['ef'] for o in objs[1:]),
              '%s: %d frames, counts %s' % (what, len(objs), [o['counts'] for o in objs]))
    # track: the per-frame lines and summary, and the JSON Lines (which send
    # the lines to standard error, compared as well); every method that
    # divides the work among threads.
    for method in ('exact', 'bvh', 'seed', 'cone'):
        what = 'track --method %s' % method
        status, out = same_for_every_count(['track', '--method', method, '--distance', '0.01']
                                           + paths, what)
        check(status == 1 and 'worst frame' in out and '; query - ms' in out,
              '%s: %d %r' % (what, status, out))
        status, out = same_for_every_count(['track', '--method', method, '--distance', '0.01',
                                            '--jsonl', '-', '--range', '0:2', pattern],
                                           what + ' --jsonl')
        objs = [json.loads(x) for x in out.splitlines()]
        check(len(objs) == 3 and objs[-1]['interferences'] > 0 and objs[-1]['contacts'] > 0 and
              objs[-1]['query_ms'] == 0, '%s: %s' % (what, objs))
    # 128 x 40 quads (10,240 triangles): with --threads 2 and 4 the refits
    # run on threads too (one per 4096 triangles, lib/hierarchy/hierarchy_refit.c).
    big, _, _ = thread_frames('big', count=2, size=(128, 40))
    status, out = same_for_every_count(['track', '--distance', '0.005'] + big, 'track BIG')
    check(status == 1 and 'worst frame' in out, 'track BIG: %d %r' % (status, out))
    status, out = same_for_every_count(['check', '--distance', '0.005', '--json', '-',
                                        '--frames'] + big, 'check --frames BIG')
    check(json.loads(out.splitlines()[-1])['counts']['ef'] > 0, 'BIG: no interference')
    # --threads=N is the same option.
    _, a, _ = run('check', '--threads=4', '--json', '-', ribbon, expect=1)
    _, b, _ = run('check', '--json', '-', ribbon, expect=1)
    check(without_times(a) == without_times(b), 'check --threads=4 differs from the default')


def test_threads_usage():
    """--threads outside 1..SELFCOL_MAX_THREADS, malformed or with white space
    is a usage error (status 2, a message naming --threads and --help), in
    check and track; info has no queries and refuses the option."""
    header = open(os.path.join(ARGS.source, 'include', 'selfcol', 'common.h')).read()
    limit = int(re.search(r'#define SELFCOL_MAX_THREADS (\d+)', header).group(1))
    paths, pattern = write_sequence('threads', [[3], [0.5]])
    mesh = paths[0]
    out_of_range = ['0', str(limit + 1), '65', '-1', '-0', '1000', '99999999999999999999999']
    malformed = ['x', '', '2x', '1.5', '2.0', '0x2', '1e1', '--quiet', '=2', '4,']
    spaced = [' 2', '2 ', '\t2', '2\n', ' ']
    for cmd in ('check', 'track'):
        for inputs in ([mesh], ['--range', '0:1', pattern]):
            for bad in out_of_range + malformed + spaced:
                for args in (['--threads', bad], ['--threads=' + bad]):
                    status, out, err = run(cmd, *(args + inputs))
                    check(status == 2, '%s %r: exit %d, expected 2 (%r)' % (cmd, args, status, err))
                    check(out == '', '%s %r: wrote %r' % (cmd, args, out))
                    check(err.startswith('selfcol-cli: ') and '--threads' in err and
                          "Try 'selfcol-cli %s --help'." % cmd in err,
                          '%s %r: message %r' % (cmd, args, err))
                    if bad in spaced:
                        check('spaces' in err, '%s %r: not refused for spaces: %r'
                              % (cmd, args, err))
                    elif bad in out_of_range:
                        check('out of range' in err and str(limit) in err,
                              '%s %r: not refused as out of range: %r' % (cmd, args, err))
            status, out, err = run(cmd, *(inputs + ['--threads']))
            check(status == 2 and "'--threads' needs a value" in err, '%s ... --threads: %r'
                  % (cmd, err))
        # The limits pass.
        for good in ('1', str(limit)):
            status, out, err = run(cmd, '--quiet', '--threads', good, mesh)
            check(status == 0 and err == '', '%s --threads %s: exit %d, %r' % (cmd, good, status,
                                                                               err))
        _, out, _ = run(cmd, '--help', expect=0)
        check(re.search(r'--threads N +threads per query(, refit and store update| and refit), 1 to %d '
                        r'\(default 1\)' % limit, out),
              '%s --help does not describe --threads' % cmd)
        check('There is no --threads' not in out, '%s --help still says there is no --threads'
              % cmd)
    status, out, err = run('info', '--threads', '2', mesh)
    check(status == 2 and 'belongs to the check and track commands' in err, 'info --threads: %r'
          % err)
    doc = open(os.path.join(ARGS.source, 'docs', 'cli.md')).read()
    check('| `--threads N` |' in doc and 'There is no `--threads`' not in doc,
          'docs/cli.md does not describe --threads')


def main():
    global ARGS
    parser = argparse.ArgumentParser()
    parser.add_argument('test')
    parser.add_argument('--cli', required=True)
    parser.add_argument('--work', required=True)
    parser.add_argument('--source', required=True)
    parser.add_argument('--shared')
    ARGS = parser.parse_args()
    test = globals().get('test_' + ARGS.test)
    if test is None:
        print('unknown test %s' % ARGS.test)
        return 2
    try:
        test()
    except Failure as failure:
        print('FAIL %s: %s' % (ARGS.test, failure))
        return 1
    print('PASS %s' % ARGS.test)
    return 0


if __name__ == '__main__':
    sys.exit(main())
