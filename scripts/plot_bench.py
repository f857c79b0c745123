#!/usr/bin/python3
"""Plots of `penumbra bench`: reads DIR/bench.json, writes DIR/accuracy.png (log-log RMSE against
wall time: the sampled curve, the exact point, the reference noise, the equal-error marker) and
DIR/scaling.png (precompute time and tree bytes against the triangle count). Needs matplotlib
(the system /usr/bin/python3 has it). Exit status 0 when the plots were written."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def accuracy(a, out):
    fig, ax = plt.subplots(figsize=(7, 5))
    pts = [p for p in a["sampled"] if p["seconds"] > 0 and p["rmse"] > 0]
    ax.loglog([p["seconds"] for p in pts], [p["rmse"] for p in pts], "o-", color="tab:blue",
              label="sampled vs exact image (rays per light)")
    for p in pts:
        ax.annotate(str(p["rays"]), (p["seconds"], p["rmse"]), textcoords="offset points",
                    xytext=(4, 4), fontsize=8, color="tab:blue")
    e = a["exact"]
    if e["seconds"] > 0 and e["rmse"] > 0:
        ax.loglog([e["seconds"]], [e["rmse"]], "D", color="tab:red", markersize=9,
                  label="exact vs converged reference")
    if a.get("referenceNoise", 0) > 0:
        ax.axhline(a["referenceNoise"], color="gray", linestyle="--", linewidth=1,
                   label="reference noise (std. error)")
    if a.get("equalErrorSeconds"):
        ax.loglog([a["equalErrorSeconds"]], [e["rmse"]], "o", markerfacecolor="none",
                  markeredgecolor="tab:green", markersize=12, markeredgewidth=2,
                  label="sampled at the exact error%s" %
                  (" (extrapolated)" if a.get("equalErrorExtrapolated") else ""))
        ax.plot([e["seconds"], a["equalErrorSeconds"]], [e["rmse"], e["rmse"]], ":",
                color="tab:green")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("RMSE (linear radiance)")
    ax.set_title("%s, %dx%d, %d spp" % (os.path.basename(a["scene"]), a["width"], a["height"],
                                        a["spp"]))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def scaling(rows, out):
    rows = [r for r in rows if r["faces"] > 0]
    if not rows:
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    f = [r["faces"] for r in rows]
    ax[0].loglog(f, [max(r["cpu"], 1e-6) for r in rows], "o-", label="CPU s")
    ax[0].loglog(f, [max(r["seconds"], 1e-6) for r in rows], "s--", label="wall s")
    ax[0].set_xlabel("faces")
    ax[0].set_ylabel("precompute time (s)")
    ax[0].legend(fontsize=8)
    ax[0].grid(True, which="both", alpha=0.3)
    built = [r for r in rows if r["bytes"] > 0]  # scenes whose pairs all failed have no tree
    ax[1].loglog([r["faces"] for r in built], [r["bytes"] for r in built], "o-", label="tree bytes")
    ax[1].loglog([r["faces"] for r in built], [max(r["nodes"], 1) for r in built], "s--",
                 label="tree nodes")
    for r in rows:
        if r["bytes"] == 0:
            ax[1].axvline(r["faces"], color="gray", linestyle=":", linewidth=1)
    ax[1].set_title("dotted: no tree built (over the limit)", fontsize=8)
    ax[1].set_xlabel("faces")
    ax[1].legend(fontsize=8)
    ax[1].grid(True, which="both", alpha=0.3)
    for r in rows:
        ax[0].annotate("%d/%d done, %d partial%s" % (r["done"], r["pairs"], r["kinds"]["partial"],
                       "" if r["complete"] else ", limit"), (r["faces"], max(r["cpu"], 1e-6)),
                       textcoords="offset points", xytext=(4, -10), fontsize=7)
    fig.suptitle("Precompute of a fixed set of receiver patches (floor + 32 model faces)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def table1(rows, out):
    """Wall time per scene: 128-ray sampling against the exact method (precompute + render)."""
    rows = [r for r in rows if "renderWall" in r["exact"]]
    if not rows:
        return
    names = [os.path.splitext(os.path.basename(r["scene"]))[0] for r in rows]
    x = range(len(rows))
    fig, ax = plt.subplots(figsize=(max(9, 1.4 * len(rows)), 4))
    w = 0.38
    ax.bar([i - w / 2 for i in x], [r["sampled128"]["wall"] for r in rows], w,
           label="sampled, 128 rays", color="#c44e52")
    pre = [r["exact"]["precomputeWall"] for r in rows]
    ren = [r["exact"]["renderWall"] for r in rows]
    ax.bar([i + w / 2 for i in x], pre, w, label="exact: precompute", color="#8172b2")
    ax.bar([i + w / 2 for i in x], ren, w, bottom=pre, label="exact: render", color="#4c72b0")
    for i, r in enumerate(rows):
        e = r["exact"]
        share = 100.0 * e.get("sampledEvaluations", 0) / max(1, e.get("evaluations", 1))
        speedup = ("%.2fx" if r["speedupWall"] < 1 else "%.1fx") % r["speedupWall"]
        ax.annotate("%s%s" % (speedup, "\n%.0f%% sampled" % share if share >= 0.5 else ""),
                    (i + w / 2, pre[i] + ren[i]), textcoords="offset points", xytext=(0, 3),
                    ha="center", fontsize=7)
    ax.set_xticks(list(x))
    ax.set_xticklabels(["%s\n%s faces\n%dx%d" % (n, r["faces"], r["width"], r["height"])
                        for n, r in zip(names, rows)], fontsize=7)
    ax.set_ylabel("wall seconds")
    ax.set_title("Table 1: exact against 128-ray sampling, %d spp" % rows[0]["spp"])
    ax.legend(fontsize=8)
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_bench.py DIR")
    d = sys.argv[1]
    with open(os.path.join(d, "bench.json")) as fh:
        b = json.load(fh)
    if b.get("table1"):
        table1(b["table1"], os.path.join(d, "table1.png"))
    if "accuracy" in b:
        accuracy(b["accuracy"], os.path.join(d, "accuracy.png"))
    if b.get("scaling"):
        scaling(b["scaling"], os.path.join(d, "scaling.png"))


if __name__ == "__main__":
    main()
