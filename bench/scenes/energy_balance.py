#!/usr/bin/env python3
"""Energy balance of a LAMMPS log of bench/scenes/in.perforation_energy.

released = W_ext - (ke + pe + W_p) is the energy the broken bonds took
away (>= 0, and it may only grow).  Energy created is the largest fall of
`released` below its running maximum (a fall anywhere in the run counts,
even after earlier releases); it is reported against the energy dissipated
at the end (W_p + released).  Usage: energy_balance.py LOG [LOG...]
Prints one line per log: created, dissipated, ratio (%)."""
import sys


def columns(path):
    lines = open(path).read().split('\n')
    heads = [k for k, l in enumerate(lines) if l.split()[:1] == ['Step']]
    if not heads:
        raise SystemExit(f"{path}: no thermo table")
    names = lines[heads[-1]].split()
    rows = []
    for l in lines[heads[-1] + 1:]:
        if l.startswith('Loop time') or l.startswith('ERROR'):
            break
        parts = l.split()
        try:
            if len(parts) == len(names):
                rows.append([float(p) for p in parts])
        except ValueError:
            pass    # a warning inside the table
    return {n: [r[k] for r in rows] for k, n in enumerate(names)}


def balance(path):
    c = columns(path)
    rel, wp = c['v_released'], c['v_wp']
    top, created = rel[0], 0.0
    for r in rel:
        top = max(top, r)
        created = max(created, top - r)
    dissipated = wp[-1] + rel[-1]
    return created, dissipated, len(rel)


if __name__ == '__main__':
    for p in sys.argv[1:]:
        created, dissipated, n = balance(p)
        print(f"{p}: created {created:.4g} dissipated {dissipated:.4g} "
              f"ratio {100 * created / dissipated:.3g} % ({n} rows)")
