#!/usr/bin/python3
"""The drive report of `ccdlane report`: replay's JSON Lines as plots over time (matplotlib)
and a summary table, in one self-contained HTML page (pictures inline, no network)."""

import argparse
import base64
import html
import io
import json
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")  # no display: files only
    import matplotlib.pyplot as plt
except ImportError:
    print("ccdlane report: matplotlib is missing: apt-get install python3-matplotlib", file=sys.stderr)
    sys.exit(1)

# tools/ccdlane/radius_text.hpp: beyond this a radius is noise on a straight road.
STRAIGHT_RADIUS_M = 10_000.0

# One colour per series, pure enough to be found in a screenshot of the page: the test
# that looks at the page in a browser reads this table from the page itself.
COLOURS = {
    "offset": "#1f4fff",
    "lane lines": "#202020",
    "warning lines": "#ff8c00",
    "lane width": "#008f3f",
    "heading": "#7f2fbf",
    "curvature": "#cf1f6f",
    "DLC left": "#0060c0",
    "DLC right": "#c00000",
    "TLC left": "#00a0a0",
    "TLC right": "#a06000",
    "LDW available": "#30b030",
    "warnings": "#ff0000",
    "not ok": "#e03090",
    "latency": "#5f5f00",
}


class BadInput(Exception):
    """A replay file that cannot be read: one line naming the file and line."""


def read_replay(path):
    frames = []
    try:
        with open(path, encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                if not line.strip():
                    continue
                try:
                    e = json.loads(line)
                except json.JSONDecodeError as error:
                    raise BadInput(f"{path}:{number}: not a replay JSON object ({error.msg})") from None
                if not isinstance(e, dict) or "frame" not in e or "t_ns" not in e or "ok" not in e:
                    raise BadInput(f"{path}:{number}: not a replay JSON object (no frame, t_ns or ok)")
                frames.append(e)
    except OSError as error:
        raise BadInput(f"{path}: cannot read ({error.strerror})") from None
    if not frames:
        raise BadInput(f"{path}: no frames")
    return frames


def value(e, *keys):
    """e[k0][k1]... as a float, NaN where absent or null."""
    for k in keys:
        if not isinstance(e, dict) or e.get(k) is None:
            return math.nan
        e = e[k]
    return float(e) if isinstance(e, (int, float)) and not isinstance(e, bool) else math.nan


def radius_text(r):
    if math.isnan(r):
        return "-"
    if math.isinf(r) or abs(r) >= STRAIGHT_RADIUS_M:
        return "straight"
    return f"{r:.0f} m"


def longest_not_ok(frames):
    """(length, first frame, last frame) of the longest run of frames not ok."""
    best, start, run = (0, None, None), None, 0
    for e in frames:
        if not e["ok"]:
            if run == 0:
                start = e["frame"]
            run += 1
            if run > best[0]:
                best = (run, start, e["frame"])
        else:
            run = 0
    return best


def summary(frames):
    n = len(frames)
    ok = sum(1 for e in frames if e["ok"])
    widths = [value(e, "lane_width_mm") for e in frames if e["ok"]]
    widths = [w for w in widths if not math.isnan(w)]
    mean = sum(widths) / len(widths) if widths else math.nan
    sd = math.sqrt(sum((w - mean) ** 2 for w in widths) / (len(widths) - 1)) if len(widths) > 1 else math.nan
    warnings = sum(1 for e in frames if (e.get("ldw") or {}).get("fired", "none") != "none")
    latencies = [value(e, "latency_us") for e in frames]
    latencies = [x for x in latencies if not math.isnan(x)]
    run, first, last = longest_not_ok(frames)
    radii = [value(e, "radius_of_curvature_m") for e in frames if e["ok"]]
    radii = [r for r in radii if not math.isnan(r)]
    tightest = min(radii, key=abs) if radii else math.nan
    span = (frames[-1]["t_ns"] - frames[0]["t_ns"]) * 1e-9
    return [
        ("frames", f"{n} ({span:.1f} s)"),
        ("ok", f"{ok} ({100.0 * ok / n:.1f} %)"),
        ("lane width", f"{mean:.0f} ± {sd:.0f} mm" if widths else "-"),
        ("tightest radius", radius_text(tightest)),
        ("warnings", str(warnings)),
        ("ms per frame", f"{sum(latencies) / len(latencies) / 1000.0:.2f}" if latencies else "-"),
        ("longest stretch not ok", f"{run} frames ({first} to {last})" if run else "none"),
    ]


def series(frames):
    """Everything plotted, as lists over the frames."""
    t = [(e["t_ns"] - frames[0]["t_ns"]) * 1e-9 for e in frames]
    s = {"t": t}
    s["offset"] = [value(e, "lateral_offset_mm") / 1000.0 for e in frames]
    s["width"] = [value(e, "lane_width_mm") / 1000.0 for e in frames]
    s["heading"] = [value(e, "heading_deg") for e in frames]
    s["curvature"] = [value(e, "curvature_per_m") * 1000.0 for e in frames]
    for side in ("left", "right"):
        s["dlc " + side] = [value(e, "ldw", f"dlc_{side}_mm") / 1000.0 for e in frames]
        s["tlc " + side] = [value(e, "ldw", f"tlc_{side}_s") for e in frames]
    s["available"] = [1.0 if (e.get("ldw") or {}).get("available") else 0.0 for e in frames]
    s["fired"] = [(e.get("ldw") or {}).get("fired", "none") for e in frames]
    s["reason"] = [e.get("reason") if not e["ok"] else None for e in frames]
    s["latency"] = [value(e, "latency_us") / 1000.0 for e in frames]
    return s


def plot_offset(ax, s, a):
    ax.plot(s["t"], s["offset"], color=COLOURS["offset"], lw=1.8, label="offset (vehicle centre, + left)")
    half = [w / 2.0 for w in s["width"]]
    # Where the front wheel's outer edge meets the earliest and latest warning lines.
    wheel = a.vehicle_width_mm / 2000.0
    earliest = [h - wheel - a.earliest_warning_mm / 1000.0 for h in half]
    latest = [h - wheel - a.latest_warning_mm / 1000.0 for h in half]
    for sign in (1, -1):
        ax.plot(s["t"], [sign * h for h in half], color=COLOURS["lane lines"], lw=1.8,
                label="lane lines" if sign > 0 else None)
        ax.plot(s["t"], [sign * x for x in earliest], color=COLOURS["warning lines"], lw=1.5, ls="--",
                label="warning lines (earliest, latest)" if sign > 0 else None)
        ax.plot(s["t"], [sign * x for x in latest], color=COLOURS["warning lines"], lw=1.5, ls=":")
    ax.set_ylabel("m")


def plot_width(ax, s, a):
    ax.plot(s["t"], s["width"], color=COLOURS["lane width"], lw=1.8, label="lane width")
    ax.set_ylabel("m")


def plot_heading(ax, s, a):
    ax.plot(s["t"], s["heading"], color=COLOURS["heading"], lw=1.8, label="heading (deg, + left)")
    ax.set_ylabel("deg")
    right = ax.twinx()
    right.plot(s["t"], s["curvature"], color=COLOURS["curvature"], lw=1.8, label="curvature (1/km, + left)")
    right.set_ylabel("1/km")
    right.legend(loc="upper right", fontsize=8)


def plot_dlc(ax, s, a):
    ax.plot(s["t"], s["dlc left"], color=COLOURS["DLC left"], lw=1.8, label="DLC left")
    ax.plot(s["t"], s["dlc right"], color=COLOURS["DLC right"], lw=1.8, label="DLC right")
    ax.set_ylabel("DLC, m")
    right = ax.twinx()
    right.plot(s["t"], s["tlc left"], color=COLOURS["TLC left"], lw=0, marker="o", ms=3, label="TLC left")
    right.plot(s["t"], s["tlc right"], color=COLOURS["TLC right"], lw=0, marker="o", ms=3, label="TLC right")
    right.set_ylabel("TLC, s")
    right.legend(loc="upper right", fontsize=8)


def plot_ldw(ax, s, a):
    ax.fill_between(s["t"], s["available"], step="post", color=COLOURS["LDW available"], alpha=1.0,
                    label="LDW available")
    for side, y in (("left", 1.3), ("right", 1.15)):
        ts = [t for t, f in zip(s["t"], s["fired"]) if f == side]
        ax.plot(ts, [y] * len(ts), color=COLOURS["warnings"], lw=0, marker="v" if side == "right" else "^", ms=9,
                label=f"warning {side}")
    ax.set_ylim(-0.1, 1.5)
    ax.set_yticks([0, 1])
    ax.set_yticklabels(["no", "yes"])


def plot_not_ok(ax, s, a):
    reasons = sorted({r for r in s["reason"] if r})
    for k, reason in enumerate(reasons):
        ts = [t for t, r in zip(s["t"], s["reason"]) if r == reason]
        ax.plot(ts, [k] * len(ts), color=COLOURS["not ok"], lw=0, marker="|", ms=14, mew=2.5)
    ax.set_yticks(range(len(reasons)))
    ax.set_yticklabels(reasons or [])
    ax.set_ylim(-0.7, max(len(reasons), 1) - 0.3)
    if not reasons:
        ax.text(0.5, 0.5, "every frame ok", transform=ax.transAxes, ha="center", va="center")


def plot_latency(ax, s, a):
    ax.plot(s["t"], s["latency"], color=COLOURS["latency"], lw=1.8, label="per frame")
    ax.set_ylabel("ms")


# (file name, title, plot function, series drawn)
PLOTS = [
    ("offset", "Lateral offset, the lane's lines and the warning lines", plot_offset,
     ["offset", "lane lines", "warning lines"]),
    ("width", "Lane width", plot_width, ["lane width"]),
    ("heading", "Heading and curvature", plot_heading, ["heading", "curvature"]),
    ("dlc-tlc", "Distance and time to line crossing (front wheels)", plot_dlc,
     ["DLC left", "DLC right", "TLC left", "TLC right"]),
    ("ldw", "Lane departure warning: availability and warnings", plot_ldw, ["LDW available", "warnings"]),
    ("not-ok", "Frames not ok, by reason", plot_not_ok, ["not ok"]),
    ("latency", "Processing time", plot_latency, ["latency"]),
]


def figure_png(title, plot, s, args):
    fig, ax = plt.subplots(figsize=(10, 2.8), dpi=90)
    plot(ax, s, args)
    ax.set_title(title, fontsize=10, loc="left")
    ax.set_xlabel("time, s")
    if len(s["t"]) > 1:  # one time axis for every plot, so that they line up
        ax.set_xlim(s["t"][0], s["t"][-1])
    ax.grid(True, color="#e0e0e0")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    out = io.BytesIO()
    fig.savefig(out, format="png")
    plt.close(fig)
    return out.getvalue()


def page(replay_path, rows, pictures):
    cells = "\n".join(f"<tr><th>{html.escape(k)}</th><td>{html.escape(v)}</td></tr>" for k, v in rows)
    figures = []
    for (name, title, _, drawn), png in zip(PLOTS, pictures):
        colours = ",".join(f"{n}:{COLOURS[n]}" for n in drawn)
        data = base64.b64encode(png).decode("ascii")
        figures.append(f'<figure data-plot="{name}" data-series="{html.escape(colours)}">'
                       f'<img alt="{html.escape(title)}" src="data:image/png;base64,{data}"></figure>')
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>ccdlane drive report: {html.escape(os.path.basename(replay_path))}</title>
<style>body{{font-family:sans-serif;margin:16px;max-width:920px}} table{{border-collapse:collapse;margin-bottom:12px}}
th,td{{border:1px solid #ccc;padding:3px 10px;text-align:left}} figure{{margin:0 0 4px 0}} img{{display:block;width:900px}}</style>
</head><body>
<h1>Drive report: {html.escape(os.path.basename(replay_path))}</h1>
<table>{cells}</table>
{chr(10).join(figures)}
</body></html>
"""


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("replay", help="ccdlane replay's JSON Lines")
    p.add_argument("--out", help="the HTML page to write")
    p.add_argument("--png", help="also write each plot as DIR/<name>.png")
    p.add_argument("--vehicle-width-mm", type=float, default=1800.0)
    p.add_argument("--earliest-warning-mm", type=float, default=750.0)
    p.add_argument("--latest-warning-mm", type=float, default=-300.0)
    args = p.parse_args()
    try:
        frames = read_replay(args.replay)
    except BadInput as error:
        print(f"ccdlane report: {error}", file=sys.stderr)
        return 2
    s = series(frames)
    pictures = [figure_png(title, plot, s, args) for _, title, plot, _ in PLOTS]
    if args.png:
        os.makedirs(args.png, exist_ok=True)
        for (name, *_), png in zip(PLOTS, pictures):
            with open(os.path.join(args.png, name + ".png"), "wb") as f:
                f.write(png)
    if args.out:
        # Whole or absent: a temporary name, then a rename.
        with open(args.out + ".part", "w", encoding="utf-8") as f:
            f.write(page(args.replay, summary(frames), pictures))
        os.replace(args.out + ".part", args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
