#!/usr/bin/python3
"""Draws `mrr bench --rule-sweep` (docs/spec.md §11): the never-slower rule on frames nobody
tuned it to.

  scripts/rule-chart.py SWEEP.json OUT_DIR

writes OUT_DIR/rule-predicted.svg (the predicted rest of each frame against the measured one,
full and mrr, and the early decision's estimate of the method's frame from its edges on against
the measured one, log-log, with the ideal y = x), OUT_DIR/rule-decisions.svg (each frame's
measured mrr/full against the early prediction, by the rule's decision, with the ±5% band) and
OUT_DIR/rule-sweep.md (the summary and every frame, a row each). A replayed sweep (`mrr bench
--rule-replay F --json OUT`) draws the same, its with-rule time "—" where only the replay falls
back (the sweep never measured that frame with the rule on)."""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")  # headless
matplotlib.rcParams["svg.hashsalt"] = "mrr"  # the same figures give the same file
import matplotlib.pyplot as plt  # noqa: E402


def early_mrr_ms(f):
    """What the early decision weighs against full's rest (docs/spec.md §11): max(floor, the edges and
    masks + E[min(R, F)]); sweeps from before the edge sample have the floor alone."""
    return f.get("predicted_mrr_early_ms", f["predicted_mrr_floor_ms"])


def estimate_mrr_ms(f):
    """The edge sample's estimate of the method's frame from its edges on (edges, masks and R̂);
    sweeps without it give what the early decision weighed."""
    return f.get("predicted_mrr_estimate_ms", early_mrr_ms(f))


def measured_early_mrr_ms(f):
    """What that predicts, measured: the method's rest and its edges and masks."""
    stages = f["mrr_stages_ms"]
    return f["measured_mrr_rest_ms"] + stages.get("edges", 0.0) + stages.get("masks", 0.0)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: rule-chart.py SWEEP.json OUT_DIR")
    sweep = json.load(open(sys.argv[1]))
    out = sys.argv[2]
    os.makedirs(out, exist_ok=True)
    frames = sweep["frames"]
    paths = sorted({f["path"] for f in frames})

    fig, axes = plt.subplots(1, len(paths), figsize=(6 * len(paths), 5), squeeze=False)
    for ax, path in zip(axes[0], paths):
        fs = [f for f in frames if f["path"] == path]
        for key, label, marker in (("full", "full", "o"), ("mrr", "mrr (rule off)", "^")):
            xs = [max(f[f"measured_{key}_rest_ms"], 1e-3) for f in fs]
            ys = [max(f[f"predicted_{key}_rest_ms"], 1e-3) for f in fs]
            ax.scatter(xs, ys, s=18, marker=marker, alpha=0.75, label=label)
        xs = [max(measured_early_mrr_ms(f), 1e-3) for f in fs]
        ys = [max(estimate_mrr_ms(f), 1e-3) for f in fs]
        label = ("mrr from its edges on, the edge sample's estimate" if fs and "predicted_mrr_estimate_ms" in fs[0]
                 else "mrr from its edges on, as the early decision weighs it")
        ax.scatter(xs, ys, s=14, marker="x", alpha=0.6, label=label)
        lo = min(min(f["measured_full_rest_ms"], f["measured_mrr_rest_ms"]) for f in fs)
        hi = max(max(f["measured_full_rest_ms"], f["measured_mrr_rest_ms"]) for f in fs)
        lo, hi = max(lo * 0.5, 1e-2), hi * 2
        ax.plot([lo, hi], [lo, hi], "k--", lw=0.8, label="ideal: predicted = measured")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("measured rest of the frame (ms)")
        ax.set_ylabel("predicted (ms)")
        ax.set_title(f"{path}: SPEC §11's prediction, {len(fs)} frames")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "rule-predicted.svg"))

    fig, axes = plt.subplots(1, len(paths), figsize=(6 * len(paths), 5), squeeze=False)
    colours = {"mrr": "tab:blue", "full": "tab:orange", "full-early": "tab:red", "full-floor": "tab:purple"}
    for ax, path in zip(axes[0], paths):
        fs = [f for f in frames if f["path"] == path]
        for decision, colour in colours.items():
            sel = [f for f in fs if f["decision"] == decision]
            if not sel:
                continue
            xs = [early_mrr_ms(f) / max(f["predicted_full_rest_ms"], 1e-9) for f in sel]
            ys = [f["mrr_ms"] / max(f["full_ms"], 1e-9) for f in sel]
            ax.scatter(xs, ys, s=18, c=colour, alpha=0.8, label=f"rule: {decision} ({len(sel)})")
            for f, x, y in zip(sel, xs, ys):
                if not f["right"]:
                    noise = "" if f.get("wrong_beyond_noise", True) else " (within noise)"
                    ax.annotate(f"{f['scene']} {f['view']}{noise}", (x, y), fontsize=6)
        ax.axhline(1.0, color="k", lw=0.8)
        ax.axhspan(1 / 1.05, 1.05, color="grey", alpha=0.2, label="±5%: either is right")
        ax.axvline(1.0, color="k", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("predicted early: mrr from its edges on / full's rest")
        ax.set_ylabel("measured mrr (rule off) / full (frame less G-buffer L0)")
        right = sum(f["right"] for f in fs)
        beyond = sum(f.get("wrong_beyond_noise", not f["right"]) for f in fs)
        ax.set_title(f"{path}: decision right on {right}/{len(fs)} frames, {beyond} wrong beyond noise")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "rule-decisions.svg"))

    s = sweep["summary"]
    replayed = sweep.get("replayed_with")
    unmeasured = s.get("rule_unmeasured", 0)
    lines = [
        f"# The never-slower rule on {s['frames']} frames nobody tuned it to",
        "",
        f"Machine: {sweep['machine']}; {sweep['threads']} threads; medians of {sweep['repeats']} runs after a warm-up, "
        "full and mrr alternating in one process (`mrr bench --rule-sweep`). Times are the frame less what every mode "
        "pays alike before the rule decides: the full-res G-buffer, and SSM's and SSGI's shadow map and one-tap test.",
        "",
    ]
    if sweep.get("cost_models") and not replayed:
        lines += ["Decided with: " + "; ".join(f"{p}: {m}" for p, m in sorted(sweep["cost_models"].items())) + ".", ""]
    if replayed:
        lines += [f"Re-decided from the recorded counts by `mrr bench --rule-replay` with: {'; '.join(replayed)}. "
                  "The times are the sweep's; \"—\": a with-rule time the sweep did not measure (only the replay "
                  "falls back there).", ""]
    lines += [
        "| frames | decision right (faster within 5%) | wrong beyond noise | kept mrr | fell back | "
        "worst mrr/full where kept | worst full/mrr where fallen back | worst with-rule/full |",
        "|---|---|---|---|---|---|---|---|",
        f"| {s['frames']} | {s['right']} ({100.0 * s['right'] / max(s['frames'], 1):.1f}%) | "
        f"{s.get('wrong_beyond_noise', '—')} | {s['kept_mrr']} | "
        f"{s['fell_back']} | {s['worst_kept_mrr_over_full']:.3f} | {s['worst_fell_back_full_over_mrr']:.3f} | "
        f"{s['worst_rule_over_full']:.3f}{f' ({unmeasured} unmeasured)' if unmeasured else ''} |",
        "",
    ]
    e = s.get("prediction_error")
    if e:  # sweeps from before it have none
        cell = lambda k: f"{100 * e[k]['rms']:.1f}% RMS, median {100 * e[k]['median']:+.1f}%"
        lines += [f"Predicted against measured: full's rest {cell('full_rest')}; the method's rest on its stencils "
                  f"{cell('mrr_rest')}; the early estimate of the method from its edges on {cell('mrr_early_estimate')}.",
                  ""]
    lines += [
        "| path | scene | view | size | effect | on geometry | ideal (px / hit) | decision | predicted mrr/full early | "
        "on the stencils | full ms | mrr ms | with rule ms | mrr/full per pair (quartiles) | right |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    def pair_quartiles(f):
        r = sorted(f.get("pair_ratios", []))
        if not r:
            return "—"
        # nearest rank, halves away from zero, as compare/rule/rule.cpp's quantile (Python's round
        # takes halves to even: with 3 pairs it would show another pair than the verdict read)
        q = lambda p: r[int(p * (len(r) - 1) + 0.5)]
        return f"{q(0.25):.2f}–{q(0.75):.2f}"

    def verdict(f):  # wrong by the medians; "within noise" when the pairs do not agree it is
        if f["right"]:
            return "yes"
        return "**no**" if f.get("wrong_beyond_noise", True) else "no, within noise"

    def with_rule(f):  # None: a replay fell back where the sweep kept the method, unmeasured
        return "—" if f["rule_ms"] is None else f"{f['rule_ms']:.1f}"

    for f in frames:
        early = early_mrr_ms(f) / max(f["predicted_full_rest_ms"], 1e-9)
        ratio = f["predicted_mrr_rest_ms"] / max(f["predicted_full_rest_ms"], 1e-9)
        lines.append(
            f"| {f['path']} | {f['scene']} | {f['view']} | {f['width']}x{f['height']} | {f['effect']}-{f['samples']} | "
            f"{100 * f['hit_share']:.0f}% | {f['ideal_speedup']:.2f} / {f['ideal_speedup_hit']:.2f} | {f['decision']} | "
            f"{early:.2f} | {ratio:.2f} | {f['full_ms']:.1f} | {f['mrr_ms']:.1f} | {with_rule(f)} | "
            f"{pair_quartiles(f)} | {verdict(f)} |")
    open(os.path.join(out, "rule-sweep.md"), "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
