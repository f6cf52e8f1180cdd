#!/usr/bin/env python3
"""The cohort's table and summary from the cases' metrics.json (no imaging: numbers and text):
  cohort.csv    one row per case: status, the error of a failed case, time per step, segments
  segments.csv  one row per case and segment: volumes, triangles, Dice and surface distance
  summary.html  the table with a thumbnail per case, and charts (time per case, volume per bone)"""
import argparse
import csv
import html
import json
import os
import statistics

CASE_COLUMNS = ["case", "status", "error", "failed_step", "seconds", "read_s", "mesh_s", "thumbnail_s", "truth_s",
                "segments", "display_triangles", "haptic_triangles", "mean_dice", "segments_without_truth", "host", "slurm_job", "input"]
SEGMENT_COLUMNS = ["case", "segment", "name", "tissue_class", "ok", "label_volume_mm3", "mesh_volume_mm3",
                   "volume_error_percent", "display_triangles", "haptic_triangles", "watertight", "truth_label",
                   "dice", "mean_surface_distance_mm", "hd95_mm", "error"]


def fmt(value, digits=3):
    if value is None or value == "":
        return ""
    if isinstance(value, float):
        return f"{value:.{digits}f}"
    return str(value)


def case_rows(metrics):
    steps = metrics.get("steps", {})
    segments = metrics.get("segments", [])
    truth = {t.get("segment"): t for t in metrics.get("truthMetrics", [])}
    # Mean Dice over segments that overlap a truth label; a segment with no truth label (e.g. a
    # bone the truth does not label) is counted apart, not averaged in as a zero.
    matched = [t for t in truth.values() if t.get("truthLabel") is not None]
    dice = [t["dice"] for t in matched if isinstance(t.get("dice"), (int, float))]
    row = {"case": metrics["case"], "status": "ok" if metrics.get("ok") else "failed", "error": metrics.get("error", ""),
           "failed_step": metrics.get("failedStep", ""), "seconds": fmt(metrics.get("seconds")),
           "read_s": fmt(steps.get("read", {}).get("seconds")), "mesh_s": fmt(steps.get("mesh", {}).get("seconds")),
           "thumbnail_s": fmt(steps.get("thumbnail", {}).get("seconds")),
           "truth_s": fmt(steps.get("truth", {}).get("seconds")), "segments": len(segments),
           "display_triangles": sum(s.get("displayTriangles") or 0 for s in segments),
           "haptic_triangles": sum(s.get("hapticTriangles") or 0 for s in segments),
           "mean_dice": fmt(statistics.mean(dice)) if dice else "",
           "segments_without_truth": len(truth) - len(matched) if truth else "", "host": metrics.get("host", ""),
           "slurm_job": metrics.get("slurmJobId", ""), "input": metrics.get("input", "")}
    seg_rows = []
    for s in segments:
        t = truth.get(s.get("id"), {})
        seg_rows.append({"case": metrics["case"], "segment": s.get("id"), "name": s.get("name"),
                         "tissue_class": s.get("tissueClass"), "ok": s.get("ok"),
                         "label_volume_mm3": fmt(s.get("labelVolumeMm3"), 1),
                         "mesh_volume_mm3": fmt(s.get("meshVolumeMm3"), 1),
                         "volume_error_percent": fmt(s.get("volumeErrorPercent")),
                         "display_triangles": s.get("displayTriangles"), "haptic_triangles": s.get("hapticTriangles"),
                         "watertight": s.get("watertight"), "truth_label": t.get("truthLabel", ""),
                         "dice": fmt(t.get("dice")), "mean_surface_distance_mm": fmt(t.get("meanSurfaceDistanceMm")),
                         "hd95_mm": fmt(t.get("hausdorff95Mm")), "error": s.get("error", "")})
    return row, seg_rows


def write_csv(path, columns, rows):
    with open(path + ".part", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    os.replace(path + ".part", path)


def bar_chart(title, unit, groups, series_names, colours, width=720, bar_height=18):
    """Horizontal bars, stacked per group: groups = [(label, [value per series])]. Inline SVG."""
    if not groups:
        return f"<p>{html.escape(title)}: nothing to show</p>"
    left, right, top = 160, 90, 40
    height = top + len(groups) * (bar_height + 6) + 40
    largest = max(sum(v for v in values if v) for _, values in groups) or 1.0
    scale = (width - left - right) / largest
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" role="img">',
             f'<text x="{width / 2}" y="20" text-anchor="middle" font-weight="bold">{html.escape(title)}</text>']
    for i, (label, values) in enumerate(groups):
        y = top + i * (bar_height + 6)
        parts.append(f'<text x="{left - 6}" y="{y + bar_height - 4}" text-anchor="end">{html.escape(label)}</text>')
        x = left
        for value, colour, name in zip(values, colours, series_names):
            if not value:
                continue
            w = value * scale
            parts.append(f'<rect x="{x:.1f}" y="{y}" width="{w:.1f}" height="{bar_height}" fill="{colour}">'
                         f'<title>{html.escape(name)}: {value:.3g} {unit}</title></rect>')
            x += w
        parts.append(f'<text x="{x + 4:.1f}" y="{y + bar_height - 4}">{sum(v for v in values if v):.3g} {unit}</text>')
    legend_y = height - 14
    for k, (name, colour) in enumerate(zip(series_names, colours)):
        parts.append(f'<rect x="{left + k * 130}" y="{legend_y - 10}" width="12" height="12" fill="{colour}"/>'
                     f'<text x="{left + k * 130 + 16}" y="{legend_y}">{html.escape(name)}</text>')
    parts.append("</svg>")
    return "\n".join(parts)


def volume_chart(seg_rows):
    """Volume per bone across the cohort: one bar group per segment name, one bar per case."""
    by_name = {}
    for r in seg_rows:
        if r["ok"] and r["label_volume_mm3"]:
            by_name.setdefault(r["name"], []).append((r["case"], float(r["label_volume_mm3"]) / 1000.0))
    groups = []
    for name in sorted(by_name):
        for case, cm3 in sorted(by_name[name]):
            groups.append((f"{name} · {case}", [cm3]))
    return bar_chart("Volume per bone across the cohort", "cm³", groups, ["segment volume (labelmap)"], ["#c9a227"])


def summary_html(rows, seg_rows, metrics_by_case, out_dir):
    ok = [r for r in rows if r["status"] == "ok"]
    times = [float(r["seconds"]) for r in ok if r["seconds"]]
    step_names = ["read", "mesh", "thumbnail", "truth"]
    colours = ["#4e79a7", "#f28e2b", "#76b7b2", "#59a14f"]
    time_groups = [(r["case"], [float(r[f"{s}_s"]) if r[f"{s}_s"] else 0.0 for s in step_names]) for r in rows]
    head = (f"<p>{len(rows)} cases: {len(ok)} succeeded, {len(rows) - len(ok)} failed. "
            + (f"Per successful case {statistics.mean(times):.1f} s on average (min {min(times):.1f}, "
               f"max {max(times):.1f}); {sum(times):.1f} s of case time in total.</p>" if times else "</p>"))
    table = ["<table><tr><th>case</th><th>thumbnail</th><th>status</th><th>time (s)</th><th>segments</th>"
             "<th>triangles (display / haptic)</th><th>mean Dice</th><th>error</th></tr>"]
    for r in rows:
        m = metrics_by_case[r["case"]]
        thumb = m.get("thumbnail")
        img = (f'<img src="cases/{html.escape(r["case"])}/{html.escape(thumb)}" width="160" alt="{html.escape(r["case"])}">'
               if thumb else "")
        status = '<span class="ok">ok</span>' if r["status"] == "ok" else '<span class="bad">failed</span>'
        table.append(f"<tr><td>{html.escape(r['case'])}</td><td>{img}</td><td>{status}</td><td>{r['seconds']}</td>"
                     f"<td>{r['segments']}</td><td>{r['display_triangles']} / {r['haptic_triangles']}</td>"
                     f"<td>{r['mean_dice']}</td><td>{html.escape(r['error'])}</td></tr>")
    table.append("</table>")
    seg_table = ["<table><tr>" + "".join(f"<th>{c}</th>" for c in SEGMENT_COLUMNS[:-1]) + "</tr>"]
    for r in seg_rows:
        seg_table.append("<tr>" + "".join(f"<td>{html.escape(str(r[c]))}</td>" for c in SEGMENT_COLUMNS[:-1]) + "</tr>")
    seg_table.append("</table>")
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>RoboPlan cohort</title>
<style>body{{font-family:sans-serif;margin:2em}} table{{border-collapse:collapse;margin:1em 0}}
td,th{{border:1px solid #ccc;padding:4px 8px;font-size:13px;vertical-align:middle}} .ok{{color:#2a7d2a}}
.bad{{color:#b22222;font-weight:bold}} svg text{{font-size:12px}}</style></head>
<body><h1>RoboPlan cohort</h1>
{head}
<h2>Cases</h2>
{''.join(table)}
<h2>Time per case</h2>
{bar_chart("Time per case, by step", "s", time_groups, step_names, colours)}
<h2>Volume per bone</h2>
{volume_chart(seg_rows)}
<h2>Segments</h2>
{''.join(seg_table)}
<p>Tables: <a href="cohort.csv">cohort.csv</a>, <a href="segments.csv">segments.csv</a>.</p>
</body></html>
"""


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--out", required=True)
    p.add_argument("metrics", nargs="+")
    args = p.parse_args()
    rows, seg_rows, by_case = [], [], {}
    for path in sorted(args.metrics):
        with open(path) as f:
            m = json.load(f)
        row, segs = case_rows(m)
        rows.append(row)
        seg_rows += segs
        by_case[m["case"]] = m
    write_csv(os.path.join(args.out, "cohort.csv"), CASE_COLUMNS, rows)
    write_csv(os.path.join(args.out, "segments.csv"), SEGMENT_COLUMNS, seg_rows)
    path = os.path.join(args.out, "summary.html")
    with open(path + ".part", "w") as f:
        f.write(summary_html(rows, seg_rows, by_case, args.out))
    os.replace(path + ".part", path)
    failed = [r for r in rows if r["status"] != "ok"]
    print(f"cohort: {len(rows) - len(failed)} of {len(rows)} cases succeeded"
          + "".join(f"\n  {r['case']}: {r['error']}" for r in failed))


if __name__ == "__main__":
    main()
