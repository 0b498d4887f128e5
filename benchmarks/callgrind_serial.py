#!/usr/bin/env python3
"""Serial fraction of the step from callgrind runs (issue 17, docs/performance.md "Serial
fraction and load balance"). Instruction counts are independent of the machine's load; memory-
bound passes (memset, memcpy) count by instruction, not by byte, so read them with that in mind.

Runs (one thread, and two threads with one file per thread), e.g. for case B with skin 0.3 and
max_steps 4 and 16 (scene copies as benchmarks/run_matched.sh writes them):
  OMP_NUM_THREADS=1 OMP_WAIT_POLICY=passive valgrind --tool=callgrind \
      --callgrind-out-file=B16.out poresph run B_16.yaml -o out16 -f -t 1      (same for B_4)
  OMP_NUM_THREADS=2 OMP_WAIT_POLICY=passive valgrind --tool=callgrind --separate-threads=yes \
      --callgrind-out-file=B16t2.out poresph run B_16.yaml -o out16t2 -f -t 2  (-> B16t2.out-01, -02)
Then:
  callgrind_serial.py serial B16.out B4.out --steps 12
      per step (difference of the two runs: set-up cancels): instructions, the serial ones
      (outside every OpenMP parallel region: not under an outlined *._omp_fn.* function), the
      serial fraction s and the Amdahl bound 1 / (s + (1 - s) / 2) at two threads, the largest
      serial functions and parallel regions. Snapshot and checkpoint writing are left out.
  callgrind_serial.py threads B16t2.out B4t2.out 12 ONE_THREAD_M
      per region the instructions of each thread, the critical path (serial + the larger thread
      of each region, summed over the steps) and the speedup it allows against ONE_THREAD_M (the
      one-thread instructions per step from `serial`).
A callee reached from serial and parallel code is split in proportion to the calls' costs (as
gprof does).
"""
import glob

import re, sys, collections

def parse(path):
    names = {}
    selfc = collections.Counter()
    arcs = collections.Counter()   # (caller, callee) -> inclusive cost
    calls = collections.Counter()
    fn = None; pending = None
    obs = {}; ob = ''; cob = None
    def name_of(tok, table=names):
        m = re.match(r'\((\d+)\)(?:\s+(.*))?$', tok)
        if m:
            i, n = m.group(1), m.group(2)
            if n is not None: table[i] = n
            return table[i]
        return tok
    with open(path, errors='replace') as f:
        for line in f:
            line = line.rstrip('\n')
            if not line: continue
            c = line[0]
            if line.startswith('ob='):
                ob = name_of(line[3:], obs).split('/')[-1]; continue
            if line.startswith('cob='):
                cob = name_of(line[4:], obs).split('/')[-1]; continue
            if line.startswith('fn='):
                fn = name_of(line[3:]) + ' [' + ob + ']'; cob = None; continue
            if line.startswith('cfn='):
                cfn = name_of(line[4:]) + ' [' + (cob if cob is not None else ob) + ']'; cob = None; continue
            if line.startswith('calls='):
                pending = (cfn, int(line.split('=')[1].split()[0])); continue
            if c.isdigit() or c in '+-*':
                parts = line.split()
                if len(parts) < 2: continue
                cost = int(parts[1])
                if pending:
                    arcs[(fn, pending[0])] += cost; calls[(fn, pending[0])] += pending[1]; pending = None
                else:
                    selfc[fn] += cost
                continue
            # other spec lines (fl=, fi=, cfl=, ob=, ...) ignored
            if line.startswith(('cfi=', 'cfl=')): continue
    return selfc, arcs, calls

def is_par(n):
    return '._omp_fn.' in n or n.startswith('GOMP_parallel')

OUTPUT = ('poresph::OutputWriter::writeSnapshot', 'poresph::OutputWriter::appendTimeseries',
          'poresph::writeCheckpoint')
def is_out(n):
    return n.startswith(OUTPUT) and '._omp_fn.' not in n

def analyse(path):
    selfc, arcs, calls = parse(path)
    out = collections.defaultdict(list)
    for (a, b), c in arcs.items(): out[a].append((b, c))
    incl = collections.Counter(selfc)
    for (a, b), c in arcs.items():
        if a != b: incl[a] += c
    incoming = collections.Counter()
    for (a, b), c in arcs.items():
        if a != b: incoming[b] += c
    # serial-context amount S(f): roots get their inclusive cost; flows along arcs proportionally
    S = collections.Counter()
    roots = [f for f in incl if incoming[f] == 0]
    for r in roots: S[r] = incl[r]
    # topological order of the call graph (Kahn); nodes left in cycles by decreasing cost
    indeg = collections.Counter()
    for (a, b) in arcs:
        if a != b: indeg[b] += 1
    ready = [f for f in incl if indeg[f] == 0]
    order = []; seen = set()
    while ready:
        f = ready.pop(); order.append(f); seen.add(f)
        for b, c in out[f]:
            if b == f: continue
            indeg[b] -= 1
            if indeg[b] == 0: ready.append(b)
    rest = sorted((f for f in incl if f not in seen), key=lambda f: -incl[f])
    if rest: print(f"(call graph: {len(rest)} functions in cycles, ordered by cost)", file=sys.stderr)
    order += rest
    out_cost = 0.0
    for f in order:
        if is_out(f):
            out_cost += S[f]; continue
        if is_par(f) or incl[f] == 0: continue
        frac = S[f] / incl[f] if incl[f] else 0
        frac = min(frac, 1.0)
        for b, c in out[f]:
            if b == f or is_par(b): continue
            S[b] += c * frac
    serial_self = {}
    for f in incl:
        if is_par(f) or is_out(f) or incl[f] == 0: continue
        frac = min(S[f] / incl[f], 1.0)
        serial_self[f] = selfc[f] * frac
    total = sum(selfc.values()) - out_cost
    serial = sum(serial_self.values())
    # parallel cost per outlined function (inclusive, from its callers = GOMP entry points)
    par = collections.Counter()
    for (a, b), c in arcs.items():
        if '._omp_fn.' in b and '._omp_fn.' not in a: par[b] += c
    return dict(out=out_cost, total=total, serial=serial, serial_self=serial_self, par=par, incl=incl, selfc=selfc, S=S)

def main_serial(argv):
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument('long'); ap.add_argument('short', nargs='?')
    ap.add_argument('--steps', type=float, default=1.0)
    ap.add_argument('--top', type=int, default=25)
    a = ap.parse_args(argv)
    L = analyse(a.long)
    if a.short:
        Sh = analyse(a.short)
    else:
        Sh = dict(out=0, total=0, serial=0, serial_self={}, par=collections.Counter(), incl=collections.Counter())
    k = a.steps
    tot = (L['total'] - Sh['total']) / k
    ser = (L['serial'] - Sh['serial']) / k
    s = ser / tot
    print(f"output (snapshots, checkpoint; left out) per step {(L['out']-Sh['out'])/k/1e6:.1f} M")
    print(f"per step: total {tot/1e6:.1f} M, serial {ser/1e6:.1f} M, s = {s:.4f}, "
          f"Amdahl 2 threads {1/(s+(1-s)/2):.3f}x")
    d = {f: (L['serial_self'].get(f, 0) - Sh['serial_self'].get(f, 0)) / k for f in set(L['serial_self']) | set(Sh['serial_self'])}
    print("top serial self costs per step:")
    for f, c in sorted(d.items(), key=lambda x: -x[1])[:a.top]:
        print(f"  {c/1e6:9.2f} M  {c/tot*100:6.2f} %  {f[:150]}")
    dp = {f: (L['par'].get(f, 0) - Sh['par'].get(f, 0)) / k for f in set(L['par']) | set(Sh['par'])}
    print("top parallel regions per step:")
    for f, c in sorted(dp.items(), key=lambda x: -x[1])[:12]:
        print(f"  {c/1e6:9.2f} M  {c/tot*100:6.2f} %  {f[:150]}")


def main_threads(argv):
    def load(prefix):
        files = sorted(glob.glob(prefix + '*-0[0-9]'))
        return [analyse(f) for f in files]

    L = load(argv[0]); S = load(argv[1]); k = float(argv[2])
    one = float(argv[3]) * 1e6 if len(argv) > 3 else None
    assert len(L) == len(S) >= 2, (len(L), len(S))
    ser = (L[0]['serial'] - S[0]['serial']) / k
    tot = [(L[t]['total'] - S[t]['total']) / k for t in range(len(L))]
    fns = set()
    for r in L + S: fns |= set(r['par'])
    rows = []
    crit = 0.0
    for fn in fns:
        c = [(L[t]['par'].get(fn, 0) - S[t]['par'].get(fn, 0)) / k for t in range(len(L))]
        crit += max(c)
        rows.append((max(c), c, fn))
    T2 = ser + crit
    work = sum(tot)
    print(f"per step at 2 threads: work {work/1e6:.1f} M (threads {', '.join(f'{x/1e6:.1f}' for x in tot)}), "
          f"serial (master) {ser/1e6:.1f} M, critical path {T2/1e6:.1f} M")
    if one:
        print(f"one-thread step {one/1e6:.1f} M: work inflation {work/one:.4f}, estimated speedup {one/T2:.3f}x")
    print("regions (per step, M instructions per thread, imbalance = max/mean):")
    for m, c, fn in sorted(rows, key=lambda x: -x[0])[:15]:
        busy = [x for x in c if x > 0]
        mean = sum(busy) / len(busy) if busy else 0
        print(f"  {' / '.join(f'{x/1e6:8.2f}' for x in c)}  imb {m/mean if mean else 0:5.3f}  {fn[:120]}")


if __name__ == '__main__':
    if len(sys.argv) < 2 or sys.argv[1] not in ('serial', 'threads'):
        sys.exit(__doc__)
    (main_serial if sys.argv[1] == 'serial' else main_threads)(sys.argv[2:])
