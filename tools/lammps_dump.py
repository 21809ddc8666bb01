"""Reading LAMMPS custom dumps for the measurement scripts of tools/."""
import numpy as np


def read_dump(path):
    """Return (timestep, dict of column -> array) of the first snapshot."""
    with open(path) as f:
        lines = f.readlines()
    step = int(lines[lines.index("ITEM: TIMESTEP\n") + 1])
    i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    cols = lines[i].split()[2:]
    data = np.array([[float(v) for v in l.split()] for l in lines[i + 1:] if l.strip()])
    return step, {c: data[:, k] for k, c in enumerate(cols)}


def damage_column(d):
    """The damage column: c_<id> of compute damage/atom or any column whose
    name contains 'dmg' or 'damage'."""
    for c in d:
        if "dmg" in c or "damage" in c:
            return d[c]
    raise SystemExit("no damage column (name containing 'dmg' or 'damage') in the dump")
