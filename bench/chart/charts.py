#!/usr/bin/python3
"""Charts (PNG) and doc tables (reStructuredText includes) from the CSVs
that chart.py run writes.  Every number on doc/Howto_choose_model.rst comes
from here.

usage: charts.py [RESULTS_DIR] [DOC_DIR]
writes RESULTS_DIR/*.png, copies them to DOC_DIR/_static/chart/ and writes
DOC_DIR/_static/chart/*.inc (tables) there too."""
import csv
import json
import math
import os
import shutil
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import models as M      # noqa: E402

import matplotlib       # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt    # noqa: E402

TARGETS = [0.10, 0.05, 0.02, 0.01]


def read(results, name):
    p = os.path.join(results, name + ".csv")
    if not os.path.exists(p):
        return []
    with open(p) as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k, v in list(r.items()):
            try:
                r[k] = float(v) if v not in ("", None) and k not in ("model", "label", "scene", "status",
                                                                      "solver", "converged", "note",
                                                                      "criterion") else v
            except ValueError:
                pass
    return rows


def ok(rows):
    return [r for r in rows if r.get("status") == "ok" and isinstance(r.get("err"), float)
            and math.isfinite(r["err"])]


def fmt(v, nd=3):
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "--"
    if v == 0:
        return "0"
    a = abs(v)
    if 1e-3 <= a < 1e5:
        return f"{v:.{nd}g}"
    return f"{v:.{max(nd - 1, 1)}e}"


def pct(v, nd=2):
    if not isinstance(v, float) or not math.isfinite(v):
        return "--"
    return f"{100 * v:.{nd}g} %" if abs(v) < 1 else f"{100 * v:.0f} %"


def table(header, rows, widths=None):
    """a list-table"""
    out = [".. list-table::", "   :header-rows: 1"]
    if widths:
        out.append("   :widths: " + " ".join(str(w) for w in widths))
    out.append("")
    for i, r in enumerate([header] + rows):
        for j, c in enumerate(r):
            out.append(("   * - " if j == 0 else "     - ") + (str(c) if str(c) else " "))
    return "\n".join(out) + "\n"


USEFUL = 1.0      # a run whose error exceeds 100 % is on no front


def pareto(points):
    """indices of the points not dominated in (cost, error): no other point is
    at most as costly and at most as wrong, and strictly better in one.
    Runs with an error above USEFUL are left out (a cheap wrong answer is no
    trade-off)."""
    idx = []
    for i, (c, e) in enumerate(points):
        if not e < USEFUL:
            continue
        dom = any((c2 <= c and e2 <= e and (c2 < c or e2 < e)) for j, (c2, e2) in enumerate(points)
                  if j != i and e2 < USEFUL)
        if not dom:
            idx.append(i)
    return sorted(idx, key=lambda i: points[i][0])


YMAX = 2.0        # errors above are drawn at the top edge of the chart
# the unstabilized classical model is never recommended: its zero-energy
# modes make its error unpredictable (plate, damage and zem scenes)
NOT_ADVISED = ("none",)


SCENE_TITLE = {"plate": "plate with a hole: sigma_yy within a radius of the hole, RMS error against CalculiX",  # noqa
               "wave": "wave in a bar: |c/c0 - 1|",
               "tension": "uniform tension: max(|E_app/E - 1|, |nu_app/nu - 1|)"}


def groups(rows):
    g = {}
    for r in rows:
        g.setdefault((int(r["dim"]), int(r["m"])), []).append(r)
    return dict(sorted(g.items(), key=lambda kv: (-kv[0][0], kv[0][1])))


def figure_legend(fig, axes):
    """one legend for the figure, with every model of every panel"""
    seen = {}
    for ax in axes.flat:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(lab, h)
    order = sorted(seen, key=lambda lab: next((i for i, k in enumerate(M.KEYS) if lab.startswith(M.LABEL[k])), 99))
    fig.legend([seen[k] for k in order], order, loc="center right", fontsize=7, frameon=False)


def error_chart(rows, scene, path):
    gs = groups(rows)
    if not gs:
        return
    fig, axes = plt.subplots(1, len(gs), figsize=(4.6 * len(gs), 4.2), squeeze=False)
    for ax, ((dim, m), rr) in zip(axes[0], gs.items()):
        for k in M.KEYS:
            pts = sorted([r for r in rr if r["model"] == k], key=lambda r: r["s_per_step"])
            if not pts:
                continue
            x = [r["s_per_step"] for r in pts]
            y = [min(max(r["err"], 1e-5), YMAX) for r in pts]
            lab = M.LABEL[k] + (" (off scale)" if any(r["err"] > YMAX for r in pts) else "")
            ax.loglog(x, y, marker=M.MARKER[k], color=M.COLOR[k], label=lab, lw=1.2, ms=5)
        P = [(r["s_per_step"], max(r["err"], 1e-5)) for r in rr]
        front = pareto(P)
        ax.step([P[i][0] for i in front], [P[i][1] for i in front], where="post", color="k", lw=0.6,
                ls="--", alpha=0.6)
        ax.set_ylim(top=YMAX * 1.3)
        ax.set_title(f"{dim}D, delta = {m} dx", fontsize=10)
        ax.set_xlabel("time per step (s, 1 core)")
        ax.grid(True, which="both", alpha=0.25)
    axes[0][0].set_ylabel("relative error")
    figure_legend(fig, axes)
    fig.suptitle(SCENE_TITLE[scene] + " (dashed: Pareto front)", fontsize=10)
    fig.tight_layout(rect=(0, 0, 0.91, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run_table(rows, scene):
    """every run of a scene (the CSV, in the doc)"""
    head = ["dim", "delta/dx", "model", "n", "dx (mm)", "points", "s/step", "point-steps/s", "MB",
            "error"]
    extra = {"plate": ["sigma_yy/S next to the hole", "FEM there (same recovery)", "solver", "force evals"],
             "wave": ["c (m/s)"],
             "tension": ["E_app (GPa)", "nu_app", "solver"]}[scene]
    body = []
    for r in rows:
        b = [int(r["dim"]), int(r["m"]), r["label"], int(r["n"]), fmt(r["dx_mm"]), int(r["natoms"]),
             fmt(r["s_per_step"]), fmt(r["point_steps_per_s"]), fmt(r["mem_mb"]), pct(r["err"], 3)]
        if scene == "plate":
            b += [fmt(r.get("kt_pd")), fmt(r.get("kt_fem_recovered")), r["solver"], int(r["steps"])]
        elif scene == "wave":
            b += [fmt(r.get("c"), 5)]
        else:
            b += [fmt(r.get("E_app"), 4), fmt(r.get("nu_app"), 3), r["solver"]]
        body.append(b)
    return table(head + extra, body)


def pareto_table(allrows):
    """per scene, dimension and horizon: the runs on the Pareto front"""
    body = []
    for scene, rows in allrows.items():
        for (dim, m), rr in groups(rows).items():
            P = [(r["s_per_step"], r["err"]) for r in rr]
            front = pareto(P)
            body.append([scene, f"{dim}D", m, ", ".join(f"{rr[i]['label']} (n={int(rr[i]['n'])}, "
                                                        f"{pct(rr[i]['err'], 2)})" for i in front)])
    return table(["scene", "dim", "delta/dx", "Pareto front, cheapest first (resolution, error)"], body,
                 [10, 6, 8, 76])


def front_all_table(allrows):
    """per scene and dimension, over both horizons and all models but the
    unstabilized one: the Pareto front (time per step against error), and
    the models on it"""
    body = []
    for scene, rows in allrows.items():
        for dim in (3.0, 2.0):
            rr = [r for r in rows if r["dim"] == dim and r["model"] not in NOT_ADVISED]
            if not rr:
                continue
            front = pareto([(r["s_per_step"], r["err"]) for r in rr])
            models = []
            for i in front:
                if rr[i]["label"] not in models:
                    models.append(rr[i]["label"])
            body.append([scene, f"{int(dim)}D", ", ".join(models),
                         "; ".join(f"{rr[i]['label']} m={int(rr[i]['m'])} n={int(rr[i]['n'])}: "
                                   f"{fmt(rr[i]['s_per_step'])} s, {pct(rr[i]['err'], 2)}" for i in front)])
    return table(["scene", "dim", "models on the front", "the front, cheapest first (horizon, resolution: "
                  "time per step, error)"], body, [8, 5, 27, 60])


def guide_table(allrows):
    """the cheapest run that meets each error target, over all models (but
    the unstabilized one), dimensions and horizons of a scene; cheapest =
    the least time to solution (the run's loop time: the whole static solve,
    or the whole wave run), which also counts a solver's iterations"""
    body = []
    for scene, rows in allrows.items():
        for tgt in TARGETS:
            good = [r for r in rows if r["err"] <= tgt and r["model"] not in NOT_ADVISED]
            if not good:
                best = min((r for r in rows if r["model"] not in NOT_ADVISED), key=lambda r: r["err"])
                body.append([scene, pct(tgt), f"none of the runs (best: {best['label']}, "
                             f"{int(best['dim'])}D, {pct(best['err'], 2)})", "", "", "", "", ""])
                continue
            r = min(good, key=lambda r: r["loop_s"])
            body.append([scene, pct(tgt), r["label"], f"{int(r['dim'])}D", int(r["m"]),
                         f"n={int(r['n'])}, dx={fmt(r['dx_mm'])} mm", f"{fmt(r['loop_s'])} s",
                         f"{fmt(r['s_per_step'])} s ({pct(r['err'], 2)})"])
    return table(["scene", "target", "cheapest model", "dim", "delta/dx", "resolution",
                  "time to solution", "time per step (error)"], body)


def best_per_model(allrows):
    """per scene: each model's best error and the cheapest run within 5 %"""
    body = []
    for scene, rows in allrows.items():
        for k in M.KEYS:
            rr = [r for r in rows if r["model"] == k]
            if not rr:
                continue
            b = min(rr, key=lambda r: r["err"])
            g = [r for r in rr if r["err"] <= 0.05]
            c = min(g, key=lambda r: r["s_per_step"]) if g else None
            body.append([scene, M.LABEL[k], pct(b["err"], 3), f"{int(b['dim'])}D m={int(b['m'])} n={int(b['n'])}",
                         (f"{fmt(c['s_per_step'])} s ({int(c['dim'])}D m={int(c['m'])} n={int(c['n'])})"
                          if c else "never")])
    return table(["scene", "model", "best error", "where", "cheapest within 5 %"], body)


def cost_table(allrows):
    """per dimension and horizon: each model's time per step relative to
    nospd silling on the same scene and resolution (median over the
    accuracy scenes and resolutions), its point-steps per second (median),
    and its memory per point: the slope of LAMMPS's per-rank memory against
    the number of points over the resolutions of each scene (median), and
    the bonds fix's own figure where it prints one"""
    base = {}
    for scene, rows in allrows.items():
        for r in rows:
            if r["model"] == "silling":
                base[(scene, r["dim"], r["m"], r["n"])] = r["s_per_step"]
    body = []
    for dim in (3.0, 2.0):
        for m in (3.0, 4.0):
            for k in M.KEYS:
                ratios, rates, slopes, bpp = [], [], [], []
                for scene, rows in allrows.items():
                    rr = [r for r in rows if r["model"] == k and r["dim"] == dim and r["m"] == m]
                    for r in rr:
                        b = base.get((scene, r["dim"], r["m"], r["n"]))
                        if b:
                            ratios.append(r["s_per_step"] / b)
                        rates.append(r["point_steps_per_s"])
                        if isinstance(r.get("bytes_per_point"), float) and math.isfinite(r["bytes_per_point"]):
                            bpp.append(r["bytes_per_point"])
                    if len(rr) >= 2:
                        a = np.array([r["natoms"] for r in rr])
                        mm = np.array([r["mem_mb"] for r in rr])
                        if a.max() > a.min():
                            slopes.append(np.polyfit(a, mm, 1)[0] * 1048576)
                if not rates:
                    continue
                body.append([f"{int(dim)}D", int(m), M.LABEL[k], fmt(float(np.median(ratios))) if ratios else "--",
                             fmt(float(np.median(rates))), fmt(float(np.median(slopes))) if slopes else "--",
                             fmt(float(np.median(bpp))) if bpp else "--"])
    return table(["dim", "delta/dx", "model", "time per step / silling's", "point-steps/s",
                  "memory slope (bytes/point)", "bonds fix (bytes/point)"], body)


# ---------------------------------------------------------------- stability

def zem_chart(results, rows, path):
    p = os.path.join(results, "zem_traces.npz")
    if not os.path.exists(p):
        return
    tr = np.load(p)
    dims = sorted({int(k.split("d_")[0]) for k in tr.files}, reverse=True)
    fig, axes = plt.subplots(1, len(dims), figsize=(5.2 * len(dims), 3.8), squeeze=False)
    c0dx = 1e-3 / math.sqrt(191e9 / 7850)
    for ax, dim in zip(axes[0], dims):
        for k in M.KEYS:
            key = f"{dim}d_{k}"
            if key not in tr.files:
                continue
            t, A = tr[key][:, 0], tr[key][:, 1]
            ax.plot(t / c0dx, A / (0.1 * t[-1]), color=M.COLOR[k], label=M.LABEL[k], lw=1.1)
        ax.set_title(f"{dim}D checkerboard mode, free NVE", fontsize=10)
        ax.set_xlabel("t c0 / dx")
        ax.grid(alpha=0.3)
    axes[0][0].set_ylabel("mode amplitude / (v0 t_end)")
    figure_legend(fig, axes)
    fig.tight_layout(rect=(0, 0, 0.8, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def drift_chart(results, path):
    p = os.path.join(results, "drift_traces.npz")
    if not os.path.exists(p):
        return
    tr = np.load(p)
    dims = sorted({int(k.split("d_")[0]) for k in tr.files}, reverse=True)
    fig, axes = plt.subplots(1, len(dims), figsize=(5.2 * len(dims), 3.8), squeeze=False)
    for ax, dim in zip(axes[0], dims):
        for k in M.KEYS:
            key = f"{dim}d_{k}"
            if key not in tr.files:
                continue
            s, rel = tr[key][:, 0], tr[key][:, 1]
            ax.plot(s, rel, color=M.COLOR[k], label=M.LABEL[k] + ("" if M.ENERGY_OK[k] else " (*)"), lw=0.9)
        ax.set_yscale("symlog", linthresh=1e-4)
        ax.set_title(f"{dim}D: (E(t) - E0)/E0, dt = 0.2 dx/c0", fontsize=10)
        ax.set_xlabel("step")
        ax.grid(alpha=0.3)
    figure_legend(fig, axes)
    fig.tight_layout(rect=(0, 0, 0.8, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def dtmax_chart(rows, path):
    rows = [r for r in rows if r.get("status") == "ok"]
    if not rows:
        return
    cases = sorted({(int(r["dim"]), int(r["m"])) for r in rows}, key=lambda c: (-c[0], c[1]))
    fig, axes = plt.subplots(1, len(cases), figsize=(4.0 * len(cases), 3.8), squeeze=False)
    for ax, (dim, m) in zip(axes[0], cases):
        rr = [r for r in rows if int(r["dim"]) == dim and int(r["m"]) == m]
        labels = [r["label"] for r in rr]
        y = np.arange(len(rr))
        ax.barh(y + 0.2, [r["dt_bounded"] for r in rr], 0.4, color=[M.COLOR[r["model"]] for r in rr],
                label="bounded")
        ax.barh(y - 0.2, [r["dt_energy1"] if isinstance(r["dt_energy1"], float) and
                          math.isfinite(r["dt_energy1"]) else 0 for r in rr], 0.4,
                color=[M.COLOR[r["model"]] for r in rr], alpha=0.45, hatch="//", label="energy within 1 %")
        est = rr[0]["dt_pmb_estimate"]
        ax.axvline(est, color="k", ls=":", lw=1)
        ax.set_yticks(y)
        ax.set_yticklabels(labels, fontsize=7)
        ax.set_xscale("log")
        ax.set_title(f"{dim}D, delta = {m} dx", fontsize=10)
        ax.set_xlabel("largest stable dt c0/dx")
    axes[0][0].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def spin_chart(rows, path):
    rows = [r for r in rows if r.get("status") == "ok"]
    if not rows:
        return
    dims = sorted({int(r["dim"]) for r in rows}, reverse=True)
    fig, axes = plt.subplots(1, len(dims), figsize=(5 * len(dims), 3.8), squeeze=False)
    for ax, dim in zip(axes[0], dims):
        for k in M.KEYS:
            rr = sorted([r for r in rows if r["model"] == k and int(r["dim"]) == dim], key=lambda r: r["angle_deg"])
            if not rr:
                continue
            y = [max(r["frms_delta_over_E"], 1e-16) for r in rr]
            ax.loglog([r["angle_deg"] for r in rr], y, marker=M.MARKER[k], color=M.COLOR[k], label=M.LABEL[k])
        ax.set_title(f"{dim}D rigid rotation: spurious force", fontsize=10)
        ax.set_xlabel("rotation angle (degrees)")
        ax.set_ylabel("RMS force density x delta / E")
        ax.grid(alpha=0.3, which="both")
    figure_legend(fig, axes)
    fig.tight_layout(rect=(0, 0, 0.8, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def stability_tables(results):
    out = {}
    z = [r for r in read(results, "zem") if r.get("status") == "ok"]
    out["zem"] = table(["dim", "model", "restoring force / (E (2a/dx)/delta)", "growth A_max/(v0 t_end)",
                        "mode frequency omega dx/c0"],
                       [[f"{int(r['dim'])}D", r["label"], fmt(r["restoring"]), fmt(r["growth"]),
                         fmt(r["omega_dx_over_c0"])] for r in z])
    d = [r for r in read(results, "drift") if r.get("status") == "ok"]
    out["drift"] = table(["dim", "model", "steps", "energy of the forces?", "drift (last - first tenth)",
                          "fluctuation (sd)", "largest error"],
                         [[f"{int(r['dim'])}D", r["label"], int(r["steps"]),
                           "yes" if M.ENERGY_OK[r["model"]] else "no", fmt(r["drift"]), fmt(r["fluctuation"]),
                           fmt(r["max_error"])] for r in d])
    t = [r for r in read(results, "dtmax") if r.get("status") == "ok"]
    out["dtmax"] = table(["dim", "delta/dx", "model", "bounded: dt c0/dx", "energy within 1 %: dt c0/dx",
                          "PMB estimate", "note"],
                         [[f"{int(r['dim'])}D", int(r["m"]), r["label"], fmt(r["dt_bounded"]),
                           fmt(r["dt_energy1"]), fmt(r["dt_pmb_estimate"]), r.get("note", "")] for r in t])
    s = [r for r in read(results, "spin") if r.get("status") == "ok"]
    angles = sorted({r["angle_deg"] for r in s})
    pick = [a for a in angles if a in (10.0, 90.0)] or angles[-1:]
    body = []
    for dim in (3, 2):
        for k in M.KEYS:
            rr = {r["angle_deg"]: r for r in s if r["model"] == k and int(r["dim"]) == dim}
            if not rr:
                continue
            b = [f"{dim}D", M.LABEL[k]]
            for a in pick:
                b += [fmt(rr[a]["energy_density_over_E"]), fmt(rr[a]["frms_delta_over_E"])]
            body.append(b)
    head = ["dim", "model"]
    for a in pick:
        head += [f"{a:g} deg: W/E", f"{a:g} deg: f delta/E"]
    out["spin"] = table(head, body)
    dm = read(results, "damage")
    if dm:
        out["damage"] = table(["model", "criterion", "steps done", "finite", "largest speed / pull speed",
                               "mean damage at the end", "largest count of singular families", "note"],
                              [[r["label"], r.get("criterion", ""), fmt(r.get("completed")), r.get("finite", ""),
                                fmt(r.get("max_speed_over_pull")), fmt(r.get("broken_fraction")),
                                fmt(r.get("singular_max")), r.get("note", "") or r.get("status", "")] for r in dm])
    else:
        out["damage"] = "No damage scene in this run.\n"
    return out


def fem_table(results):
    f = read(results, "plate_fem")
    if not f:
        return "CalculiX was not available: no FEM reference in this run.\n"
    return table(["plane", "nu", "elements (quarter)", "Kt FEM (ccx)", "Heywood", "Kirsch"],
                 [[r["plane"], fmt(r["nu"]), int(r["elements"]), fmt(r["kt_fem"], 5), fmt(r["kt_heywood"], 4),
                   "3"] for r in f])


def main(results, doc):
    figs = os.path.join(results)
    allrows = {}
    for scene in ("plate", "wave", "tension"):
        rows = ok(read(results, scene))
        if rows:
            allrows[scene] = rows
            error_chart(rows, scene, os.path.join(figs, f"chart_{scene}.png"))
    zem_chart(results, read(results, "zem"), os.path.join(figs, "stab_zem.png"))
    drift_chart(results, os.path.join(figs, "stab_drift.png"))
    dtmax_chart(read(results, "dtmax"), os.path.join(figs, "stab_dtmax.png"))
    spin_chart(read(results, "spin"), os.path.join(figs, "stab_spin.png"))
    incs = {"pareto": pareto_table(allrows), "guide": guide_table(allrows), "cost": cost_table(allrows),
            "front": front_all_table(allrows),
            "best": best_per_model(allrows), "fem": fem_table(results)}
    for scene, rows in allrows.items():
        incs[f"runs_{scene}"] = run_table(rows, scene)
    incs.update(stability_tables(results))
    sk = [r for r in read(results, "skipped") if r.get("model")]
    incs["skipped"] = ("Every model ran.\n" if not sk else
                       "Not in this run (the plugin or LAMMPS lacks the style): " +
                       ", ".join(sorted({f"{r['label']}" for r in sk})) + ".\n")
    info_p = os.path.join(results, "run_info.json")
    info = json.load(open(info_p)) if os.path.exists(info_p) else {}
    incs["info"] = (f"Generated from the run of {info.get('date', '?')} (size *{info.get('size', '?')}*, "
                    f"{info.get('jobs', '?')} LAMMPS processes at a time on a {info.get('host_cores', '?')}-core "
                    f"machine, {info.get('seconds', '?')} s in all).\n")
    if doc:
        dst = os.path.join(doc, "_static", "chart")
        os.makedirs(dst, exist_ok=True)
        for f in os.listdir(dst):          # nothing stale from an older run
            if f.endswith((".png", ".inc")):
                os.remove(os.path.join(dst, f))
        for f in os.listdir(figs):
            if f.endswith(".png"):
                shutil.copy(os.path.join(figs, f), os.path.join(dst, f))
        for k, v in incs.items():
            with open(os.path.join(dst, k + ".inc"), "w") as fh:
                fh.write(".. generated by bench/chart/charts.py from bench/chart/results: do not edit\n\n" + v)
    print(f"charts in {figs}" + (f"; doc figures and tables in {doc}/_static/chart" if doc else ""))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "results"),
         sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "..", "..", "doc"))
