#!/usr/bin/python3
"""Checks of the PERI-NOSPD documentation, run by ctest (unittest/docs).

usage:
  check_docs.py pages    LMP DOCDIR          every registered style has a page
  check_docs.py examples LMP DOCDIR WORKDIR  every page's example lines run
  check_docs.py sphinx   DOCDIR OUTDIR       sphinx -W (warnings are errors)
  check_docs.py materials LMP POTDIR WORKDIR every material of every file loads

LMP is the LAMMPS executable; the plugin must be auto-loaded through
LAMMPS_PLUGIN_PATH (material files are found through LAMMPS_POTENTIALS).

Style -> page mapping ("pages")
-------------------------------
An accelerator variant (NAME ending in "/omp") belongs on its base style's
page, which must carry ".. index:: KIND NAME" and "Accelerator Variants:
*NAME*", as LAMMPS's own pages do.
`plugin list` prints one line per registered style, e.g.
"2: fix style plugin PERI_NEIGH/NOSPD".  The page of a style of kind KIND
(pair, fix, compute, bond, ...) and name NAME is

    doc/KIND_NAME'.rst      NAME' = NAME lowercased, every "/" -> "_"

(pair peri/nospd -> pair_peri_nospd.rst, fix PERI_NEIGH/NOSPD ->
fix_peri_neigh_nospd.rst, compute nospd/atom -> compute_nospd_atom.rst), the
names LAMMPS's own doc/src uses.  A "command" style maps to NAME'.rst.  The
page's title (its first heading) must contain the style name.

Example lines ("examples")
--------------------------
Every doc/*.rst page with a section titled "Examples" contributes the lines
of the literal blocks in that section (``.. code-block::``,
``.. parsed-literal::`` or a paragraph ending in "::"); "&" continues a line.
  * A pair_style line and the pair_coeff lines after it form one group, run
    as one deck.  The point spacing is the smallest horizon (last number of
    a pair_coeff line before its inelastic keywords) / 3.01, the number of atom types the largest type
    number in the pair_coeff lines (types fill slabs along x).
  * Every other line (compute, fix, dump, variable, thermo_style, ...) runs
    in its own deck with the most recent pair group of the same page, or
    with the default pair style (peri/nospd, material steel of
    potentials/materials.nospd, spacing 10 mm, horizon 30.1 mm: a 0.1 m
    block), after the earlier lines of the page that it refers to (c_ID,
    f_ID, v_NAME, ${NAME}, X_modify ID, a group ID; a min_modify line the
    page's min_style line).  A group the line names
    (its group-ID argument, or the word after a "group" keyword) that no
    earlier line defines is created holding all atoms.  Equal-style
    variables are evaluated.
  * Dimension: a deck is 2D when its pair_style line has the keyword
    "plane" or a comment line just above the line says "dimension 2" (3D
    when it says "dimension 3"); otherwise it runs in 3D and, if that
    fails, in 2D: a line passes when it runs in either.
  * Setup commands that the deck itself makes (units, atom_style, lattice,
    create_box, read_data, run, plugin, ...) are not run.
Each deck is a block of 10^3 (2D: 10^2) points with atom_style peri, units
si, and ends with "run 0"; a deck fails on a nonzero exit status or an
"ERROR" in its log.

Material files ("materials")
----------------------------
Every POTDIR/*.nospd file must start with the LAMMPS metadata line
"# DATE: ... UNITS: si CONTRIBUTOR: ... CITATION: ...", every material line
must have five words (name E nu density G0, numbers in range; inelastic
keywords may follow, and then G0 may be 0) with a
comment directly above its entry naming the source, and LAMMPS must load
every material through "pair_coeff I I FILE NAME delta" (one deck, one atom
type per material, run 0).

"""
import os
import re
import shutil
import subprocess
import sys

SKIP_RETURN_CODE = 77

# commands the deck provides itself, or that would end or replace it
SETUP_COMMANDS = {
    "units", "atom_style", "atom_modify", "dimension", "boundary", "lattice", "create_box",
    "create_atoms", "read_data", "read_restart", "read_dump", "write_restart", "write_data",
    "write_dump", "write_coeff", "clear", "log", "include", "shell", "echo", "quit", "run",
    "rerun", "minimize", "plugin", "newton", "processors", "package", "suffix", "print",
    "next", "jump", "label"}


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


# ---------------------------------------------------------------- styles

def registered_styles(lmp):
    """(kind, name) of every style the auto-loaded plugins register."""
    res = subprocess.run([lmp, "-log", "none", "-echo", "none", "-nocite"], input="plugin list\n",
                         capture_output=True, text=True, timeout=120)
    out = res.stdout + res.stderr
    if res.returncode != 0:
        fail(f"'{lmp}' with 'plugin list' exited with {res.returncode}:\n{out}")
    styles = re.findall(r"^\s*\d+:\s+(\S+) style plugin (\S+)\s*$", out, re.M)
    if not styles:
        fail("'plugin list' shows no plugin styles: is LAMMPS_PLUGIN_PATH set to the folder "
             f"of nospdplugin.so?\n{out}")
    return styles


# Aliases are documented on the page of the style they stand for, which
# must name them (e.g. pair nospd, registered so that pair hybrid can hold
# peri/nospd beside LAMMPS's peri/lps: PERI_NEIGH looks its pair up by "peri").
ALIASES = {("pair", "nospd"): "peri/nospd", ("pair", "nospd/hs"): "peri/nospd/hs"}


def accelerated(name):
    """The base style of an accelerator variant (peri/nospd/omp -> peri/nospd), else None."""
    return name[: -len("/omp")] if name.endswith("/omp") else None


def page_name(kind, name):
    # accelerator variants live on their base style's page, as in LAMMPS's docs
    if accelerated(name):
        name = accelerated(name)
    name = ALIASES.get((kind, name), name)
    base = name.lower().replace("/", "_")
    return f"{base}.rst" if kind == "command" else f"{kind.lower()}_{base}.rst"


def first_heading(text):
    lines = text.splitlines()
    for i in range(len(lines) - 1):
        if lines[i].strip() and re.fullmatch(r"([=\-~\"'^#*+`])\1+", lines[i + 1].strip()) \
                and not lines[i].startswith(".."):
            return lines[i].strip()
    return ""


def check_pages(lmp, docdir):
    styles = registered_styles(lmp)
    bad = []
    for kind, name in styles:
        path = os.path.join(docdir, page_name(kind, name))
        if not os.path.isfile(path):
            bad.append(f"{kind} style {name}: no page {path}")
            continue
        text = open(path, encoding="utf-8").read()
        title = first_heading(text)
        if accelerated(name):
            word = "pair_style" if kind == "pair" else kind
            if not re.search(r"^\.\. index:: " + re.escape(word) + r"\s+" + re.escape(name) + r"\s*$",
                             text, re.M) or \
                    not re.search(r"Accelerator Variants:.*\*" + re.escape(name) + r"\*", text):
                bad.append(f"{kind} style {name} (accelerator variant): {os.path.basename(path)} "
                           f"needs '.. index:: {word} {name}' and 'Accelerator Variants: *{name}*'")
            else:
                print(f"ok   {kind} {name} (accelerator variant) -> doc/{os.path.basename(path)}")
            continue
        if (kind, name) in ALIASES:
            if not re.search(r"pair_style\s+" + re.escape(name) + r"\b", text):
                bad.append(f"{kind} style {name} (alias): {os.path.basename(path)} never "
                           f"shows 'pair_style {name}'")
            else:
                print(f"ok   {kind} {name} (alias) -> doc/{os.path.basename(path)}")
            continue
        if name.lower() not in title.lower():
            bad.append(f"{kind} style {name}: the title of {os.path.basename(path)} "
                       f"('{title}') does not name the style")
        else:
            print(f"ok   {kind} {name} -> doc/{os.path.basename(path)}")
    if bad:
        fail("styles without a proper doc page:\n  " + "\n  ".join(bad))
    print(f"PASS: {len(styles)} registered styles, each with its page")


# ---------------------------------------------------------------- examples

def is_underline(line, title):
    s = line.strip()
    return bool(title.strip()) and len(s) >= len(title.strip()) and \
        re.fullmatch(r"([=\-~\"'^#*+`])\1+", s) is not None


def examples_section(text):
    """Lines of the section titled 'Examples' (None if the page has none)."""
    lines = text.splitlines()
    start = None
    for i in range(len(lines) - 1):
        if lines[i].strip() == "Examples" and is_underline(lines[i + 1], lines[i]):
            start = i + 2
            break
    if start is None:
        return None
    end = len(lines)
    for i in range(start, len(lines) - 1):
        if lines[i].strip() and not lines[i][0].isspace() and not lines[i].startswith("..") \
                and is_underline(lines[i + 1], lines[i]):
            end = i
            break
    return lines[start:end]


def literal_lines(section):
    """Input lines of the literal blocks of a section, '&' continuations joined."""
    out = []
    i = 0
    n = len(section)
    while i < n:
        line = section[i]
        stripped = line.strip()
        opener = (stripped.startswith(".. code-block::") or stripped.startswith(".. code::")
                  or stripped.startswith(".. parsed-literal::")
                  or (stripped.endswith("::") and not stripped.startswith("..")))
        if not opener:
            i += 1
            continue
        indent = len(line) - len(line.lstrip())
        i += 1
        # directive options (":caption: ...") right after the directive
        while i < n and section[i].strip().startswith(":") and stripped.startswith(".."):
            i += 1
        block = []
        while i < n:
            l = section[i]
            if l.strip() and len(l) - len(l.lstrip()) <= indent:
                break
            block.append(l)
            i += 1
        joined = ""
        for l in block:
            s = l.strip()
            if not s:
                if joined:
                    out.append(joined)
                    joined = ""
                out.append("")
                continue
            joined = (joined + " " + s) if joined else s
            if joined.endswith("&"):
                joined = joined[:-1].rstrip()
                continue
            out.append(joined)
            joined = ""
        if joined:
            out.append(joined)
        out.append("")
    return out


def numeric(tok):
    try:
        float(tok)
        return True
    except ValueError:
        return False


def type_bound(tok):
    """Largest type number a pair_coeff type argument names (0 for '*')."""
    nums = [int(v) for v in re.findall(r"\d+", tok)]
    return max(nums) if nums else 0


class Deck:
    def __init__(self, dim=3, pair=None, forced=False, groups=()):
        self.dim = dim
        self.forced = forced      # dimension set by a hint on the page
        self.pair = pair or []    # pair_style + pair_coeff lines
        self.groups = list(groups)    # group IDs to create with all atoms

    def spacing_and_types(self):
        deltas, ntypes = [], 1
        for line in self.pair:
            w = line.split()
            if w[0] == "pair_coeff" and len(w) >= 3:
                ntypes = max(ntypes, type_bound(w[1]), type_bound(w[2]))
                # the horizon is the last number before the inelastic
                # keywords (the first word after I J that starts with a letter
                # and follows a number)
                head = w
                for k in range(4, len(w)):
                    if w[k][0].isalpha() and numeric(w[k - 1]):
                        head = w[:k]
                        break
                if numeric(head[-1]):
                    deltas.append(float(head[-1]))
        dx = min(deltas) / 3.01 if deltas else (0.001 if self.pair else 0.01)
        return dx, ntypes

    def thickness(self):
        for line in self.pair:
            w = line.split()
            if w[0] == "pair_style" and "thickness" in w:
                k = w.index("thickness")
                if k + 1 < len(w) and numeric(w[k + 1]):
                    return float(w[k + 1])
        return 1.0

    def text(self, body):
        dx, ntypes = self.spacing_and_types()
        n = 10
        head = ["units si", f"dimension {self.dim}", "atom_style peri", "atom_modify map array"]
        if self.dim == 3:
            head += ["boundary s s s", f"lattice sc {dx!r}", f"region box block 0 {n} 0 {n} 0 {n}"]
            vol = dx ** 3
        else:
            head += ["boundary s s p", f"lattice sq {dx!r}",
                     f"region box block 0 {n} 0 {n} -0.5 0.5"]
            vol = dx * dx * self.thickness()
        head += [f"create_box {ntypes} box", "create_atoms 1 box"]
        for t in range(2, ntypes + 1):
            lo = (t - 1) * n / ntypes
            head += [f"region nospd_slab{t} block {lo:.6g} INF INF INF INF INF",
                     f"set region nospd_slab{t} type {t}"]
        head += ["set group all density 1000.0", f"set group all volume {vol!r}",
                 f"neighbor {0.3 * dx!r} bin"]
        pair = self.pair or ["pair_style peri/nospd",
                             f"pair_coeff * * materials.nospd steel {3.01 * dx!r}"]
        # a small nonuniform displacement, so that forces are not all zero
        head += pair + ["displace_atoms all ramp x 0.0 1.0e-7 y 0.0 1.0 units box"]
        head += [f"group {g} union all" for g in self.groups]
        return "\n".join(head + body + ["thermo_style custom step pe", "run 0"]) + "\n"


REF_RE = re.compile(r"\b([cfv])_([A-Za-z0-9_]+)|\$\{([A-Za-z0-9_]+)\}|\$([A-Za-z0-9_])\b")


def references(line):
    """(kind, ID) pairs a line refers to."""
    refs = []
    for m in REF_RE.finditer(line):
        if m.group(1):
            refs.append(({"c": "compute", "f": "fix", "v": "variable"}[m.group(1)], m.group(2)))
        else:
            refs.append(("variable", m.group(3) or m.group(4)))
    w = line.split()
    if w[0].endswith("_modify") and len(w) > 1 and w[0] not in ("atom_modify", "neigh_modify",
                                                                 "comm_modify", "thermo_modify",
                                                                 "pair_modify", "box_modify",
                                                                 "min_modify"):
        refs.append((w[0][:-len("_modify")], w[1]))
    # a min style's own min_modify keywords need that style set first
    if w[0] == "min_modify":
        refs.append(("min_style", ""))
    if w[0] in ("compute", "fix", "dump") and len(w) > 2:
        refs.append(("group", w[2]))
    for k in range(3, len(w) - 1):
        if w[k] == "group":
            refs.append(("group", w[k + 1]))
    if w[0] == "group" and "variable" in w:
        k = w.index("variable")
        if k + 1 < len(w):
            refs.append(("variable", w[k + 1]))
    # "region ID" inside a command (group ... region ID, a keyword's region)
    for k in range(1, len(w) - 1):
        if w[k] == "region":
            refs.append(("region", w[k + 1]))
    return refs


def definition(line):
    w = line.split()
    if w[0] in ("compute", "fix", "dump", "variable", "group", "region") and len(w) > 1:
        return (w[0], w[1])
    if w[0] == "min_style":
        return ("min_style", "")
    return None


def page_tests(lines):
    """[(description, Deck, body lines)] for the example lines of one page."""
    tests = []
    pending_dim = None
    group = None          # current pair group (a Deck)
    defs = {}             # (kind, ID) -> (line, its own dependencies)
    for line in lines:
        if not line:
            pending_dim = None
            continue
        if line.startswith("#"):
            if re.search(r"dimension\s+2|\b2d\b", line, re.I):
                pending_dim = 2
            elif re.search(r"dimension\s+3|\b3d\b", line, re.I):
                pending_dim = 3
            continue
        w = line.split("#")[0].split()
        if not w:
            continue
        line = " ".join(w)
        cmd = w[0]
        if cmd == "pair_style":
            forced = pending_dim is not None or "plane" in w
            dim = 2 if (pending_dim == 2 or "plane" in w) else 3
            group = Deck(dim, [line], forced)
            tests.append([f"'{line}' and its pair_coeff lines", group, []])
            pending_dim = None
            continue
        if cmd == "pair_coeff":
            if group is None:
                fail(f"example line '{line}' has no pair_style line before it")
            group.pair.append(line)
            continue
        if cmd in SETUP_COMMANDS:
            print(f"skip {line}   (setup command: the test deck makes its own)")
            continue
        dim = pending_dim or (group.dim if group else 3)
        forced = pending_dim is not None or (group.forced if group else False)
        # earlier lines this one needs, in page order, dependencies first;
        # groups that no earlier line defines are made from all atoms
        need, todo, auto = [], [line], []
        while todo:
            cur = todo.pop()
            # a word naming a group of an earlier line (a keyword's group, as
            # fix nospd/heat's fixed, convection and flux take)
            named = [("group", x) for x in cur.split()[3:] if ("group", x) in defs]
            for ref in references(cur) + named:
                if ref in defs and defs[ref] not in need and defs[ref] != line:
                    need.append(defs[ref])
                    todo.append(defs[ref])
                elif ref[0] == "group" and ref not in defs and ref[1] != "all" \
                        and ref[1] not in auto:
                    auto.append(ref[1])
        deck = Deck(dim, list(group.pair) if group else None, forced, auto)
        order = [l for l in defs.values() if l in need]
        body = order + [line]
        d = definition(line)
        if cmd == "variable" and len(w) > 2 and w[2] == "equal":
            body = body + ["run 0", f'print "{w[1]} = ${{{w[1]}}}"']
        tests.append([f"'{line}'", deck, body])
        if d:
            defs[d] = line
    return tests


def run_deck(lmp, workdir, name, text):
    os.makedirs(workdir, exist_ok=True)
    path = os.path.join(workdir, f"in.{name}")
    with open(path, "w") as f:
        f.write(text)
    log = os.path.join(workdir, f"log.{name}")
    res = subprocess.run([lmp, "-in", path, "-log", log, "-screen", "none", "-nocite"],
                         cwd=workdir, capture_output=True, text=True, timeout=300)
    out = (open(log).read() if os.path.exists(log) else "") + res.stdout + res.stderr
    errors = [l for l in out.splitlines() if "ERROR" in l]
    ok = res.returncode == 0 and not errors
    return ok, path, errors or out.splitlines()[-5:]


def check_examples(lmp, docdir, workdir):
    if os.path.isdir(workdir):
        shutil.rmtree(workdir)
    pages = sorted(f for f in os.listdir(docdir) if f.endswith(".rst"))
    ntests, failures = 0, []
    for page in pages:
        section = examples_section(open(os.path.join(docdir, page), encoding="utf-8").read())
        if section is None:
            continue
        tests = page_tests(literal_lines(section))
        if not tests:
            failures.append(f"{page}: its Examples section has no input lines")
            continue
        for k, (desc, deck, body) in enumerate(tests):
            ntests += 1
            name = f"{page[:-4]}.{k + 1}"
            ok, path, msg = run_deck(lmp, workdir, name, deck.text(body))
            if not ok and not deck.forced:
                # no dimension hint on the page: the line may need 2D
                deck.dim = 5 - deck.dim
                ok2, path2, msg2 = run_deck(lmp, workdir, name + "_2d", deck.text(body))
                if ok2:
                    ok, path = ok2, path2
                else:
                    deck.dim = 5 - deck.dim
                    msg = list(msg) + [f"and in 2D ({path2}):"] + list(msg2)
            print(f"{'ok  ' if ok else 'FAIL'} {page}: {desc}  ({deck.dim}D deck {path})")
            if not ok:
                failures.append(f"{page}: {desc} -> {path}\n      " + "\n      ".join(msg))
    if failures:
        fail(f"{len(failures)} of {ntests} example decks failed:\n  " + "\n  ".join(failures))
    if ntests == 0:
        fail(f"no example lines found in {docdir}")
    print(f"PASS: {ntests} example decks from the doc pages ran")


# ---------------------------------------------------------------- materials

def material_entries(path):
    """[(name, E, nu, rho, G0)] of a material file; fails on a bad file."""
    lines = open(path, encoding="utf-8").read().splitlines()
    head = lines[0] if lines else ""
    for key in ("DATE:", "UNITS: si", "CONTRIBUTOR:", "CITATION:"):
        if not head.startswith("#") or key not in head:
            fail(f"{path}: line 1 must be the LAMMPS metadata comment with '{key}'")
    entries = []
    for k, raw in enumerate(lines):
        words = raw.split("#")[0].split()
        if not words:
            continue
        where = f"{os.path.basename(path)}:{k + 1}"
        if len(words) < 5:
            fail(f"{where}: a material line has 5 words (name E nu density G0) and optional "
                 f"inelastic keywords: '{raw}'")
        if len(words) > 5 and not words[5][0].isalpha():
            fail(f"{where}: after the 5 numbers only inelastic keywords may follow: '{raw}'")
        inelastic = len(words) > 5
        words = words[:5]
        try:
            E, nu, rho, g0 = (float(v) for v in words[1:])
        except ValueError:
            fail(f"{where}: E nu density G0 must be numbers: '{raw}'")
        # G0 = 0 (none given) only for inelastic metals that fail by plastic strain
        if not (E > 0 and -1 < nu < 0.5 and rho > 0 and (g0 > 0 or (inelastic and g0 == 0))):
            fail(f"{where}: values out of range (E > 0, -1 < nu < 0.5, density > 0, G0 > 0; "
                 "G0 = 0 allowed for inelastic entries)")
        if k == 0 or not lines[k - 1].lstrip().startswith("#"):
            fail(f"{where}: material '{words[0]}' has no source comment directly above it")
        if any(e[0] == words[0] for e in entries):
            fail(f"{where}: material '{words[0]}' appears twice")
        entries.append((words[0], E, nu, rho, g0))
    if not entries:
        fail(f"{path}: no materials")
    return entries


def check_materials(lmp, potdir, workdir):
    files = sorted(f for f in os.listdir(potdir) if f.endswith(".nospd"))
    if not files:
        fail(f"no *.nospd material files in {potdir}")
    for fname in files:
        entries = material_entries(os.path.join(potdir, fname))
        n = len(entries)
        body = ["units si", "boundary s s s", "atom_style peri", "atom_modify map array",
                "lattice sc 0.001", f"region box block 0 {4 * n} 0 4 0 4",
                f"create_box {n} box", "create_atoms 1 box"]
        for t in range(2, n + 1):
            body += [f"region m{t} block {4 * (t - 1) - 0.5} INF INF INF INF INF",
                     f"set region m{t} type {t}"]
        body += ["set group all volume 1.0e-9", "pair_style peri/nospd"]
        for t, (name, _, _, rho, _) in enumerate(entries, start=1):
            body += [f"pair_coeff {t} {t} {os.path.abspath(os.path.join(potdir, fname))} "
                     f"{name} 0.00301",
                     f"set type {t} density {rho!r}"]
        body += ["run 0"]
        ok, path, msg = run_deck(lmp, workdir, fname.replace(".", "_"), "\n".join(body) + "\n")
        if not ok:
            fail(f"LAMMPS could not load every material of {fname} ({path}):\n  "
                 + "\n  ".join(msg))
        print(f"ok   {fname}: " + ", ".join(e[0] for e in entries))
    print(f"PASS: {len(files)} material file(s) well formed and loaded by LAMMPS")


# ---------------------------------------------------------------- sphinx

def check_sphinx(docdir, outdir):
    try:
        import sphinx  # noqa: F401
    except ImportError:
        print(f"SKIP: Sphinx is not installed for {sys.executable} "
              "(Debian: apt-get install python3-sphinx); the doc build was not checked")
        sys.exit(SKIP_RETURN_CODE)
    if os.path.isdir(outdir):
        shutil.rmtree(outdir)
    cmd = [sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
           "-d", os.path.join(outdir, ".doctrees"), docdir, outdir]
    print(" ".join(cmd))
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    sys.stdout.write(res.stdout + res.stderr)
    if res.returncode != 0:
        fail(f"sphinx -W exited with {res.returncode} (warnings are errors)")
    print(f"PASS: sphinx -W built {outdir}")


def main(argv):
    if len(argv) >= 3 and argv[0] == "pages":
        check_pages(argv[1], argv[2])
    elif len(argv) >= 4 and argv[0] == "examples":
        check_examples(argv[1], argv[2], argv[3])
    elif len(argv) >= 4 and argv[0] == "materials":
        check_materials(argv[1], argv[2], argv[3])
    elif len(argv) >= 3 and argv[0] == "sphinx":
        check_sphinx(argv[1], argv[2])
    else:
        print(__doc__)
        sys.exit(2)


if __name__ == "__main__":
    main(sys.argv[1:])
