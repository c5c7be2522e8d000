"""The pages of `mrr compare --report DIR` and `mrr bench --report DIR`, and the bench's charts.

mrr compiles this file and templates/*.html.j2 into its binary, writes them to a scratch
folder and runs `/usr/bin/python3 report.py DATA.json PAGE.html` (compare/report/report_python.cpp).
DATA.json holds what C++ measured, with "kind": "compare", "bench" or "check" (the index of
`mrr check --report`). This program writes the
page to PAGE.html (mrr then moves it into place) and, for the bench, every chart as SVG and
PNG into DIR/charts/. Any failure is an exception; mrr shows its last line.
"""
import base64
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # headless: no display is ever needed
matplotlib.rcParams["svg.hashsalt"] = "mrr"  # the SVG's ids: the same figures give the same file
import jinja2  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))

# The methods, as the bench's JSON carries mrr's method table (common/methods.h: "methods"): one
# colour and marker per method on every chart, their chart order, the reference (full) and the
# paper's method (mrr). use_methods() loads them before any chart is drawn.
METHODS = []   # names in chart order
COLOR = {}
MARKER = {}
REFERENCE = None  # the table's reference row's name
PAPER = None      # the table's paper row's name
# A method's bench variants ("mrr-effect+c4+p0.3", "mrr+norule"): each its own colour, the same on
# every chart of a report (the variants a bench ran, by name, take these in turn:
# assign_variant_colors), and a pentagon; a lone "+norule" its own purple cross.
VARIANT_COLORS = ["#e377c2", "#bcbd22", "#17a589", "#c49c94", "#6b6ecf", "#e7ba52"]
VARIANT_COLOR = {}
NORULE_STYLE = ("#9467bd", "X")


def use_methods(rows):
    """Loads the method table's rows (name, chart_order, colour, marker, reference, paper)."""
    global REFERENCE, PAPER
    rows = sorted(rows, key=lambda r: r["chart_order"])
    METHODS[:] = [r["name"] for r in rows]
    COLOR.clear()
    MARKER.clear()
    for r in rows:
        COLOR[r["name"]] = r["colour"]
        MARKER[r["name"]] = r["marker"]
        if r.get("reference"):
            REFERENCE = r["name"]
        if r.get("paper"):
            PAPER = r["name"]


def base_of(method):
    """The table row a bench method names ("mrr-effect+c4" -> "mrr-effect")."""
    return method.split("+")[0]


def assign_variant_colors(methods):
    VARIANT_COLOR.clear()
    variants = sorted(m for m in set(methods) if "+" in m and not m.endswith("+norule"))
    for i, m in enumerate(variants):
        VARIANT_COLOR[m] = VARIANT_COLORS[i % len(VARIANT_COLORS)]


def color_of(method):
    if method.endswith("+norule") and method.count("+") == 1:
        return NORULE_STYLE[0]
    return COLOR.get(method) or VARIANT_COLOR.get(method, "#000000")


def marker_of(method):
    if method.endswith("+norule") and method.count("+") == 1:
        return NORULE_STYLE[1]
    return MARKER.get(method, "p" if "+" in method else "o")


PAPER_COLOR = "#2ca02c"
WIDTH, HEIGHT = 880, 560  # pixels of the PNG (the SVG has the same proportions)


def pareto_front(points):
    """Indices of the Pareto-optimal (x, y) points when x (error) is minimised and y (speedup)
    maximised: a point is dropped when another has x <= and y >= with one of them strict (so
    exact duplicates both stay). Points with a non-finite coordinate are dropped. Sorted by x,
    then y descending, then index: the order the front's line joins them."""
    finite = [i for i, (x, y) in enumerate(points) if math.isfinite(x) and math.isfinite(y)]

    def beaten(i):
        xi, yi = points[i]
        return any(points[j][0] <= xi and points[j][1] >= yi and tuple(points[j]) != (xi, yi) for j in finite)

    return sorted((i for i in finite if not beaten(i)), key=lambda i: (points[i][0], -points[i][1], i))


def method_order(methods):
    """The chart order of the table; a method's variants right after it, by name."""
    def rank(m):
        b = base_of(m)
        return (METHODS.index(b) if b in METHODS else len(METHODS), m != b, m)
    return sorted(set(methods), key=rank)


def distinct(items):
    """The values in first-seen order."""
    return list(dict.fromkeys(items))


def size_name(r):
    return "%dx%d" % (r["width"], r["height"])


# ---- Charts ----------------------------------------------------------------------------------

class Chart:
    """One figure: a title, a grey subtitle (the machine), matplotlib's default look."""

    def __init__(self, name, title, subtitle, caption, xlabel, ylabel):
        self.name, self.caption, self.title = name, caption, title
        self.fig, self.ax = plt.subplots(figsize=(WIDTH / 100, HEIGHT / 100), dpi=100)
        self.fig.suptitle(title, fontweight="bold")
        self.ax.set_title(subtitle, fontsize=9, color="#666666")
        self.ax.set_xlabel(xlabel)
        self.ax.set_ylabel(ylabel)
        self.ax.grid(True, color="#e5e5e5")
        self.ax.set_axisbelow(True)

    def guide(self, y, label):
        self.ax.axhline(y, color="#7f7f7f", linestyle="--", linewidth=1)
        self.ax.annotate(label, (1, y), xycoords=("axes fraction", "data"), xytext=(-3, 3),
                         textcoords="offset points", ha="right", fontsize=8, color="#7f7f7f")

    def bars(self, categories, series):
        """Grouped bars: series is [(method, {category: value})], side by side in 80% of a slot."""
        width = 0.8 / max(len(series), 1)
        for k, (method, values) in enumerate(series):
            xs = [categories.index(c) - 0.4 + (k + 0.5) * width for c in values]
            self.ax.bar(xs, list(values.values()), width, label=method, color=color_of(method))
        self.ax.set_xticks(range(len(categories)), categories, rotation=20 if len(categories) > 4 else 0,
                           ha="right" if len(categories) > 4 else "center")
        self.ax.set_ylim(bottom=0)

    def legend_entries(self):
        """The (handles, labels) of every axes of the figure (a twin axis too), in drawing order."""
        handles, labels = [], []
        for ax in self.fig.axes:
            h, l = ax.get_legend_handles_labels()
            handles += h
            labels += l
        return handles, labels

    def save(self, folder):
        """SVG and PNG, each written under a temporary name and renamed into place."""
        handles, labels = self.legend_entries()
        if handles:
            self.ax.legend(handles, labels, fontsize=9)
        self.fig.tight_layout()
        for ext in ("svg", "png"):
            path = os.path.join(folder, self.name + "." + ext)
            temporary = os.path.join(folder, ".%s.tmp-%d.%s" % (self.name, os.getpid(), ext))
            # No date in the SVG, so that the same figures give the same file.
            self.fig.savefig(temporary, format=ext, dpi=100, metadata={"Date": None} if ext == "svg" else None)
            os.replace(temporary, path)
        plt.close(self.fig)


def plot_method(ax, method, xs, ys, label=None, line=True, ideal=False):
    ys = [math.nan if y is None else y for y in ys]  # JSON's null: a figure that was not finite
    ax.plot(xs, ys, label=label or method, color=color_of(method),
            marker=marker_of(method), linestyle=("--" if ideal else "-") if line else "none",
            markerfacecolor="white" if ideal else None, markersize=6)


def speed_vs_rms(path, effect, runs, device, key="rms"):
    """Chart 1: measured speedup against RMS (or, key "flip", against mean FLIP; key
    "rms_expectation", against the effect's expectation, full's own point included), one point
    per method and setting, the Pareto front."""
    flip, expected = key == "flip", key == "rms_expectation"
    figure = "FLIP" if flip else "RMS"
    c = Chart("speed-vs-%s-%s-%s" % (key.replace("_", "-"), path, effect),
              "Speed against %s, %s (%s path)" % (
                  "perceived error (FLIP)" if flip else "accuracy (against the effect's expectation)" if expected else "accuracy",
                  effect, path), device,
              "Chart 1%s (%s, %s): one point per method × scene × camera × setting; up and left is better. The dashed "
              "line joins the points no other point beats on both axes. Frames with %s 0 (mrr falling back to "
              "full) sit at the left end of the axis.%s" % (
                  "b" if flip else "c" if expected else "", path, effect, figure,
                  " FLIP: the mean LDR-FLIP of the effect buffer shown as grey, at 67 pixels per degree: the error "
                  "a viewer sees, where RMS weighs every pixel alike." if flip else
                  " The error against the effect's expectation (full's mean over other seeds, SPEC §10): full's own "
                  "points are the estimator's noise, which no method shades away." if expected else ""),
              "%s (log)" % ("mean FLIP against full" if flip else "RMS against the expectation" if expected
                            else "RMS against full"), "measured speedup over full (x)")
    others = [r for r in runs if expected or r["method"] != REFERENCE]
    # A log axis cannot show an error of 0 (frames the never-slower rule shaded at full res):
    # they are drawn at a third of the smallest non-zero error, which the caption says.
    floor = min([r[key] / 3 for r in others if r.get(key) and r[key] > 0] or [1.0])
    points = []
    for m in method_order(r["method"] for r in others):
        mine = [(r[key] if r[key] and r[key] > 0 else floor, r["measured_speedup"])
                for r in others if r["method"] == m and r.get(key) is not None]
        plot_method(c.ax, m, [p[0] for p in mine], [p[1] for p in mine], line=False)
        points += mine
    front = [points[i] for i in pareto_front(points)]
    c.ax.plot([p[0] for p in front], [p[1] for p in front], "k--", linewidth=1, label="Pareto front")
    c.ax.set_xscale("log")
    c.guide(1.0, REFERENCE if expected else "full (%s 0)" % figure)
    return c


def shares_axis(ours, theirs):
    """Whether the paper's x values can share our axis: where at least half of our span (in
    octaves; a single value: the value itself) lies inside the paper's. Otherwise (a --quick
    bench at 54 and 90 pixels against the paper's 720 to 2160) ours would be squeezed into a
    corner of an axis drawn for theirs, and the paper gets its own."""
    lo, hi = min(ours), max(ours)
    inside_lo, inside_hi = max(lo, min(theirs)), min(hi, max(theirs))
    if hi <= lo:
        return inside_lo <= inside_hi
    return inside_hi > inside_lo and math.log2(inside_hi / inside_lo) >= 0.5 * math.log2(hi / lo)


def sweep(figure, path, effect, runs, paper, device):
    """The paper's Fig. 6 (speedup against samples), 7 (against resolution) or 9 (RMS against
    resolution), with the paper's own figures drawn beside ours (green, hollow, dashed). By
    resolution, where our heights and the paper's hardly overlap, the paper's curve has its own
    x axis along the top (green): each curve then spans the chart, read against its own axis."""
    first = runs[0]
    by_samples, rms = figure == "fig6", figure == "fig9"
    x_of = (lambda r: r["samples"]) if by_samples else (lambda r: r["height"])
    title = {"fig6": "Speedup against samples, %s at %s (Fig. 6)" % (effect, size_name(first)),
             "fig7": "Speedup against resolution, %s-%d (Fig. 7)" % (effect, first["samples"]),
             "fig9": "RMS against resolution, %s-%d (Fig. 9)" % (effect, first["samples"])}[figure]
    caption = {"fig6": "Measured (solid) and ideal (dashed, mrr) speedup; the paper's Fig. 6, measured at 4K on a "
                       "GTX 1080, in green.",
               "fig7": "Measured (solid) and ideal (dashed, mrr) speedup by resolution; the paper's Fig. 7 in green "
                       "(it loses 17% for SSM at 720p; mrr's never-slower rule keeps it at or above 1).",
               "fig9": "RMS of each method against full at the same samples; the paper's Fig. 9 in green."}[figure]
    c = Chart("%s-%s-%s" % (figure, path, effect), title, "%s; %s, camera 0" % (device, first["scene"]), caption,
              "samples per pixel (log)" if by_samples else "image height (pixels)",
              "RMS against full" if rms else "speedup over full (x)")
    for m in method_order(r["method"] for r in runs):
        if m == REFERENCE:
            continue
        mine = sorted((r for r in runs if r["method"] == m), key=x_of)
        xs = [x_of(r) for r in mine]
        plot_method(c.ax, m, xs, [r["rms" if rms else "measured_speedup"] for r in mine],
                    label=m if rms else m + " measured")
        if m == PAPER and not rms:
            plot_method(c.ax, m, xs, [r["ideal_speedup"] for r in mine], label="%s ideal (pixels)" % m, ideal=True)
            if all("ideal_speedup_hit" in r for r in mine):  # over pixels on geometry: what full pays for
                c.ax.plot(xs, [r["ideal_speedup_hit"] for r in mine], label="%s ideal (pixels on geometry)" % m,
                          color=color_of(m), linestyle=":", marker=marker_of(m),
                          markerfacecolor="white", markersize=5)
    theirs = sorted((p for p in paper if p["figure"] == figure and p["effect"] == effect),
                    key=lambda p: p["samples"] if by_samples else p["height"])
    if theirs:
        their_x = [p["samples"] if by_samples else p["height"] for p in theirs]
        own_axis = not by_samples and not shares_axis([x_of(r) for r in runs], their_x)
        ax = c.ax
        if own_axis:
            ax = c.ax.twiny()  # the same y (speedup or RMS), the paper's heights along the top
            ax.set_xlabel("the paper's image height (pixels): its own axis", color=PAPER_COLOR)
            ax.tick_params(axis="x", colors=PAPER_COLOR)
            c.ax.set_xlabel("our image height (pixels)")
            c.caption += (" The paper's heights (%d to %d) hardly overlap ours (%d to %d): its curve is read "
                          "against the green axis along the top." % (min(their_x), max(their_x),
                                                                      min(x_of(r) for r in runs),
                                                                      max(x_of(r) for r in runs)))
        ax.plot(their_x, [p["rms"] if rms else p["speedup"] for p in theirs], color=PAPER_COLOR, linestyle="--",
                marker="D", markerfacecolor="white",
                label="paper, Fig. %s (GTX 1080%s%s)" % (figure[3:], ", at 4K" if by_samples else "",
                                                        ", top axis" if own_axis else ""))
    if by_samples:
        c.ax.set_xscale("log")
    if not rms:
        c.guide(1.0, REFERENCE)
    return c


def stress(path, effect, runs, device):
    """Measured speedup of every method on each stress scene (+norule: without the rule)."""
    c = Chart("stress-%s-%s" % (path, effect), "Stress scenes, %s: measured speedup (%s path)" % (effect, path),
              device, "Each stress scene models one failure: bumpy normals (edges explode), wires thinner than a "
              "coarse pixel, an image that is all edges, and one with none (builtin:plane). +norule is the "
              "method without the never-slower rule.", "scene", "measured speedup over full (x)")
    scenes = distinct(r["scene"] for r in runs)
    c.bars(scenes, [(m, {r["scene"]: r["measured_speedup"] for r in runs if r["method"] == m})
                    for m in method_order(r["method"] for r in runs) if m != REFERENCE])
    c.guide(1.0, REFERENCE)
    return c


def flicker(path, stability, device, key="flicker"):
    """Chart 4: SPEC §10 flicker of each method along each camera path; with key="flip_flicker",
    the same for the FLIP map (the frame-to-frame change of FLIP against full)."""
    s0 = stability[0]
    flip = key == "flip_flicker"
    c = Chart("flicker-" + path + ("-flip" if flip else ""),
              "%s along camera paths (%s path)" % ("FLIP flicker" if flip else "Flicker", path),
              "%s; %d frames at %s" % (device, s0["frames"], size_name(s0)),
              ("Chart 4b: the frame-to-frame change of each method's LDR-FLIP map against full, per pixel (SPEC §10); "
               "lower is steadier. FLIP has no sign: an error that only changes sign does not count, one that comes "
               "and goes does." if flip else
               "Chart 4: the frame-to-frame change of each method's error against full (SPEC §10); lower is steadier."),
              "scene, camera path, effect",
              "FLIP flicker: mean |FLIP(t) - FLIP(t-1)|" if flip else "flicker: mean |error(t) - error(t-1)|")
    label = lambda s: "%s %s %s" % (s["scene"], s["camera_path"], s["effect"])  # noqa: E731
    c.bars(distinct(label(s) for s in stability),
           [(m, {label(s): s[key] for s in stability if s["method"] == m})
            for m in method_order(s["method"] for s in stability)])
    return c


# ---- The foveation group (SPEC §13; compare/bench/bench_fovea.cpp) -----------------------

def fovea_style(method):
    """A method's colour; its "+gaze" or "+motion" run drawn solid, the method alone dashed."""
    base = method.split("+gaze")[0].split("+motion")[0]
    limited = "+gaze" in method or "+motion" in method
    return color_of(base), "-" if limited or base == REFERENCE else "--", marker_of(base)


def ring_label(r):
    return ("> %g°" % r["from_degrees"]) if r["to_degrees"] is None else "%g–%g°" % (r["from_degrees"], r["to_degrees"])


def fovea_rings(path, scene, ppd, rings, device, key):
    """Per eccentricity ring, one line per method: the shaded share (key "shaded_share"), the RMS
    ("rms") or the mean FLIP ("flip") against full; each legend entry carries the frame's time."""
    r0 = rings[0]
    what = {"shaded_share": "shaded share", "rms": "RMS against full", "flip": "mean FLIP against full"}[key]
    c = Chart("fovea-%s-%s-%s-ppd%g" % (key.replace("_", "-"), path, scene.replace(":", "-"), round(ppd, 2)),
              "Foveation, %s per eccentricity ring: %s, ppd %.2f (%s path)" % (what, scene, ppd, path),
              "%s; %s %s-%d, gaze at the centre (%d, %d)" % (device, size_name(r0), r0["effect"], r0["samples"],
                                                              r0["gaze"][0], r0["gaze"][1]),
              "The %s in each ring of eccentricity around the gaze (SPEC §13). Dashed: the method with the gaze only "
              "measuring (--foveate off), its own decisions; solid: with the gaze foveating (+gaze). The legend gives "
              "each frame's effect time (less its full-res G-buffer and shaded image, SPEC §10; median of the repeats).%s" % (
                  what, "" if key == "shaded_share" else " A ring with no error (0) has no point on the log axis."),
              "eccentricity ring", what + (" (log)" if key != "shaded_share" else ""))
    labels = distinct(ring_label(r) for r in rings)
    for m in distinct(r["method"] for r in rings):
        if key != "shaded_share" and m == REFERENCE:
            continue  # 0 against itself
        of = [r for r in rings if r["method"] == m]
        color, style, marker = fovea_style(m)
        # On the log axes a ring with no error (tiles' full-rate centre) has no point.
        ys = [r[key] if key == "shaded_share" or r[key] > 0 else math.nan for r in of]
        c.ax.plot([labels.index(ring_label(r)) for r in of], ys, color=color, linestyle=style,
                  marker=marker, label="%s (%.0f ms)" % (m, of[0]["effect_ms"]))
    c.ax.set_xticks(range(len(labels)), labels)
    if key == "shaded_share":
        c.ax.set_ylim(bottom=0)
        c.guide(1.0, REFERENCE)
    else:
        c.ax.set_yscale("log")
    return c


def fovea_motion(path, scene, motion, device):
    """Shaded share against the frame's mean screen speed along the camera paths, each method
    without and with the previous path frame; the time on the right axis, hollow markers."""
    m0 = motion[0]
    c = Chart("fovea-motion-%s-%s" % (path, scene.replace(":", "-")),
              "Motion: shaded share against screen speed, %s (%s path)" % (scene, path),
              "%s; %s %s-%d, %s, %d frames each" % (device, size_name(m0), m0["effect"], m0["samples"],
                                                   " and ".join(distinct(m["camera_path"] for m in motion)), m0["frames"]),
              "Each frame of the camera paths after the first: the mean |v| over pixels on geometry (SPEC §13 step 3, "
              "the previous path frame as --prev-frame) against the share of pixels shaded (filled, left axis) and the "
              "frame's effect time (less its full-res G-buffer and shaded image; hollow, right axis, median of the repeats). Points alone: the "
              "method without the previous frame (its share follows the frame's content); joined: with it (+motion).",
              "mean screen speed |v| (full-res pixels per frame)", "shaded level pixels / W·H")
    right = c.ax.twinx()
    right.set_ylabel("effect time (ms)")
    for m in distinct(r["method"] for r in motion):
        of = sorted((r for r in motion if r["method"] == m), key=lambda r: r["mean_speed"])
        color, style, marker = fovea_style(m)
        xs = [r["mean_speed"] for r in of]
        # the static method's share follows the frame's content, not the speed: points, no line
        c.ax.plot(xs, [r["shaded_share"] for r in of], color=color, linestyle="-" if "+motion" in m else "none",
                  marker=marker, label=m)
        right.plot(xs, [r["effect_ms"] for r in of], color=color, linestyle="none", marker=marker,
                   markerfacecolor="white", alpha=0.7, label=m + " ms")
    c.ax.set_ylim(bottom=0)
    right.set_ylim(bottom=0)
    return c


def fovea_charts(fovea, devices):
    out = []
    rings, motion = fovea.get("rings", []), fovea.get("motion", [])
    for path in distinct(r["path"] for r in rings + motion):
        device = devices.get(path, path)
        for scene in distinct(r["scene"] for r in rings if r["path"] == path):
            for ppd in distinct(r["ppd"] for r in rings if r["path"] == path and r["scene"] == scene):
                sel = [r for r in rings if r["path"] == path and r["scene"] == scene and r["ppd"] == ppd]
                out += [fovea_rings(path, scene, ppd, sel, device, k) for k in ("shaded_share", "rms", "flip")]
        for scene in distinct(r["scene"] for r in motion if r["path"] == path):
            out.append(fovea_motion(path, scene, [r for r in motion if r["path"] == path and r["scene"] == scene],
                                    device))
    return out


def bench_charts(results, paper):
    """Every chart, in the order the page shows them."""
    runs, out = results["runs"], []
    use_methods(results["methods"])
    assign_variant_colors([r.get("method", "") for r in runs] + [s["method"] for s in results["stability"]])
    for path in distinct(r["path"] for r in runs):
        device = results["devices"].get(path, path)
        of_path = [r for r in runs if r["path"] == path]
        for effect in distinct(r["effect"] for r in of_path):
            group = lambda g: [r for r in of_path if r["group"] == g and r["effect"] == effect]  # noqa: E731
            if group("main"):
                out.append(speed_vs_rms(path, effect, group("main"), device))
                if all("flip" in r for r in group("main")):  # bench JSON from before FLIP has none
                    out.append(speed_vs_rms(path, effect, group("main"), device, key="flip"))
                if all("rms_expectation" in r for r in group("main")):  # bench --expectation
                    out.append(speed_vs_rms(path, effect, group("main"), device, key="rms_expectation"))
            if group("samples"):
                out.append(sweep("fig6", path, effect, group("samples"), paper, device))
            if group("resolution"):
                out += [sweep(f, path, effect, group("resolution"), paper, device) for f in ("fig7", "fig9")]
            if group("stress"):
                out.append(stress(path, effect, group("stress"), device))
        stability = [s for s in results["stability"] if s["path"] == path]
        if stability:
            out.append(flicker(path, stability, device))
            if all("flip_flicker" in s for s in stability):  # bench JSON from before FLIP has none
                out.append(flicker(path, stability, device, key="flip_flicker"))
    out += fovea_charts(results.get("fovea", {}), results["devices"])
    return out


# ---- Pages -----------------------------------------------------------------------------------

def environment(work):
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(os.path.join(HERE, "templates")),
                             autoescape=True, undefined=jinja2.StrictUndefined, trim_blocks=True, lstrip_blocks=True)

    def data_uri(name):
        """A PNG that mrr wrote into the scratch folder, embedded (the page fetches nothing)."""
        with open(os.path.join(work, name), "rb") as f:
            return "data:image/png;base64," + base64.b64encode(f.read()).decode("ascii")

    env.filters["data_uri"] = data_uri
    return env


def bench_page(data, env):
    out_dir = data["out_dir"]
    os.makedirs(os.path.join(out_dir, "charts"), exist_ok=True)
    figures = []
    for chart in bench_charts(data["results"], data["paper"]):
        chart.save(os.path.join(out_dir, "charts"))
        figures.append({"name": chart.name, "title": chart.title, "caption": chart.caption})
    # Example images, written by the sweep: each method on the same frame.
    examples, images = [], os.path.join(out_dir, "images")
    if os.path.isdir(images):
        for group in sorted(g for g in os.listdir(images) if os.path.isdir(os.path.join(images, g))):
            present = [m for m in METHODS if os.path.exists(os.path.join(images, group, m + ".png"))]
            examples.append({"group": group, "methods": present})
    return env.get_template("bench.html.j2").render(figures=figures, examples=examples, **data)


def main(argv):
    if len(argv) != 3:
        raise SystemExit("usage: report.py DATA.json PAGE.html")
    with open(argv[1], encoding="utf-8") as f:
        data = json.load(f)
    env = environment(os.path.dirname(os.path.abspath(argv[1])))
    if data["kind"] == "bench":
        page = bench_page(data, env)
    elif data["kind"] == "check":
        page = env.get_template("check.html.j2").render(**data)
    else:
        page = env.get_template("compare.html.j2").render(**data)
    with open(argv[2], "w", encoding="utf-8") as f:
        f.write(page)


if __name__ == "__main__":
    main(sys.argv)
