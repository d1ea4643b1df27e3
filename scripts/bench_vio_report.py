#!/usr/bin/python3
"""Tables of scripts/bench_vio.sh from its run folders (OUT/runs/LABEL/RUN/summary.yaml): per set,
one row per run with each label's ATE [m] and ATE in % of the distance travelled, then the
aggregates (mean, median, max, sequences over 0.3 %, better/worse than the first label, the
geometric mean of the per-sequence ATE ratios against the first label), the speed (median over
runs of the real-time factor and of the per-frame back-end median) and, for runs with
`report_relative_covariance`, the median over runs of the mean NEES (pose, position, yaw; consistent:
6, 3, 1) and of the share within the 95 % bound.
Usage: bench_vio_report.py OUT --manifest FILE --labels "L1 L2 ..."
"""
import argparse
import math
import os
import re
import statistics


def read_run(path):
    """dict of the summary's numbers, or None when the run failed or is missing."""
    summary = os.path.join(path, "summary.yaml")
    if os.path.exists(os.path.join(path, "failed")) or not os.path.exists(summary):
        return None
    values = {}
    for key in ("ate_se3_rmse_m", "gt_length_m", "realtime_factor", "backend_median",
                "solve_median", "resets", "frontend_median"):
        m = re.search(r"^\s*%s: ([0-9.eE+-]+)" % key, open(summary).read(), re.M)
        if m:
            values[key] = float(m.group(1))
    m = re.search(r"^nees_relative: \{([^}]*)\}", open(summary).read(), re.M)
    if m:
        for item in m.group(1).split(","):
            key, value = item.split(":")
            values["nees_" + key.strip()] = float(value)
    return values


def runs_of(out, label, name):
    """All repeats of a run name (NAME or NAME_rK)."""
    d = os.path.join(out, "runs", label)
    if not os.path.isdir(d):
        return []
    pattern = re.compile(r"^%s(_r\d+)?$" % re.escape(name))
    return [read_run(os.path.join(d, n)) for n in sorted(os.listdir(d)) if pattern.match(n)]


def fmt(v, spec="%.3f"):
    return "-" if v is None else spec % v


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--manifest", required=True)
    ap.add_argument("--labels", required=True)
    args = ap.parse_args()
    labels = args.labels.split()
    sets = {}
    for line in open(args.manifest):
        head = line.split("|")[0].split()
        if len(head) != 3:
            continue
        set_name, name, masks = head
        for mask in masks.split(","):
            sets.setdefault(set_name, []).append(name if mask == "none" else "%s_mask_%s" % (name, mask))

    for set_name, names in sets.items():
        print("\n### %s\n" % set_name)
        print("| run | " + " | ".join("%s ATE m (%%)" % l for l in labels) + " |")
        print("|---|" + "---|" * len(labels))
        ate = {l: {} for l in labels}
        pct = {l: {} for l in labels}
        rtf = {l: [] for l in labels}
        backend = {l: [] for l in labels}
        resets = {l: 0 for l in labels}
        nees = {l: {} for l in labels}
        for name in names:
            cells = []
            for l in labels:
                runs = [r for r in runs_of(args.out, l, name)]
                ok = [r for r in runs if r and "ate_se3_rmse_m" in r]
                if not runs:
                    cells.append("-")
                    continue
                if not ok:
                    cells.append("failed")
                    continue
                r = ok[0]  # deterministic output: every repeat has the same ATE
                ate[l][name] = r["ate_se3_rmse_m"]
                if r.get("gt_length_m"):
                    pct[l][name] = 100.0 * r["ate_se3_rmse_m"] / r["gt_length_m"]
                rtf[l] += [x["realtime_factor"] for x in ok if "realtime_factor" in x]
                backend[l] += [x["backend_median"] for x in ok if "backend_median" in x]
                resets[l] += int(r.get("resets", 0))
                for key in ("nees_pose", "nees_position", "nees_yaw", "nees_within_95"):
                    if key in r:
                        nees[l].setdefault(key, []).append(r[key])
                cells.append("%.3f (%s)" % (ate[l][name], fmt(pct[l].get(name), "%.2f")))
            print("| %s | %s |" % (name, " | ".join(cells)))

        def row(title, fn):
            print("| **%s** | %s |" % (title, " | ".join(fn(l) for l in labels)))

        def stat(values, f):
            return f(values) if values else None
        row("mean %", lambda l: fmt(stat(list(pct[l].values()), statistics.mean), "%.3f"))
        row("median %", lambda l: fmt(stat(list(pct[l].values()), statistics.median), "%.3f"))
        row("max %", lambda l: fmt(stat(list(pct[l].values()), max), "%.3f"))
        row("over 0.3 %", lambda l: "%d of %d" % (sum(v > 0.3 for v in pct[l].values()), len(pct[l])))
        row("median ATE m", lambda l: fmt(stat(list(ate[l].values()), statistics.median)))
        row("mean ATE m", lambda l: fmt(stat(list(ate[l].values()), statistics.mean)))
        base = labels[0]

        def ratio(l):
            common = [n for n in ate[l] if n in ate[base] and ate[base][n] > 0 and ate[l][n] > 0]
            if not common:
                return "-"
            g = math.exp(statistics.mean(math.log(ate[l][n] / ate[base][n]) for n in common))
            better = sum(ate[l][n] < ate[base][n] for n in common)
            return "x%.3f (%d/%d better)" % (g, better, len(common))
        row("ATE vs %s (geo. mean)" % base, ratio)
        row("real-time factor (median, min)", lambda l: "%s, %s" % (
            fmt(stat(rtf[l], statistics.median), "%.2f"), fmt(stat(rtf[l], min), "%.2f")))
        row("back-end ms (median of medians)", lambda l: fmt(stat(backend[l], statistics.median), "%.1f"))
        row("resets", lambda l: "%d" % resets[l])
        if any(nees[l] for l in labels):
            row("NEES pose / position / yaw (median of means; consistent 6 / 3 / 1)", lambda l: " / ".join(
                fmt(stat(nees[l].get(k, []), statistics.median), "%.2f")
                for k in ("nees_pose", "nees_position", "nees_yaw")))
            row("within the 95 % bound (median; consistent 0.95)",
                lambda l: fmt(stat(nees[l].get("nees_within_95", []), statistics.median), "%.2f"))


if __name__ == "__main__":
    main()
