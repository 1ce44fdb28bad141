#!/usr/bin/env python3
"""Plots and an HTML report from a conftrack performance folder.

Usage: python3 scripts/conftrack_plots.py OUTPUT_DIR

Reads summary.json and the CSV files that conftrack writes there
(include/conftrack/evaluation/PerformanceReport.hpp describes them) and
writes PNG plots and index.html into the same folder:
  efficiency versus pT, theta, phi, production radius and proximity (the
  CLICdp plot cuts of evaluation.md A1), fake rate versus pT and theta,
  duplicate rate versus pT and theta, resolutions versus pT at the nominal
  polar angles (single-particle samples; with the ideal-resolution anchors
  of evaluation.md B5 as dashed lines for CLICdet and CLD), pulls, and the
  CPU time per finding step and per event.
For ttbar samples the report puts the CLICdp validation numbers of
evaluation.md B1/B2 next to ours.

Needs matplotlib and numpy (Debian: apt-get install python3-matplotlib
python3-numpy). Without them it writes index.html with the tables and the
list of CSV files only, and exits with code 3.
"""
import csv
import html
import json
import math
import os
import sys

MISSING_MATPLOTLIB_EXIT = 3
INSTALL_HINT = "apt-get install python3-matplotlib python3-numpy"

# ---------------------------------------------------------------------------
# Reference numbers (evaluation.md). Readings of plots: about +-0.5 %
# absolute for efficiencies and +-30 % relative for fake rates.

# B2, ttbar at 3 TeV, CLIC_o3_v14. (label, csv, x range, kind, fold theta,
# reference without background, reference with 30 BX gg->hadrons). The x
# range selects the CSV bins that overlap it; "kind" is how ours is shown.
TTBAR_REFERENCE = [
    ("Efficiency, pT > 1 GeV (10° < θ < 170°, R < 50 mm, ΔR > 0.02)",
     "efficiency_vs_pt", (1.0, 1e9), "pct", False, "≈ 99.7–100 %", "≈ 99.5–100 %"),
    ("Efficiency at pT ≈ 0.1 GeV", "efficiency_vs_pt", (0.1, 0.11), "pct",
     False, "≈ 92.5 %", "≈ 81–83 %"),
    ("Efficiency at pT ≈ 0.2 GeV", "efficiency_vs_pt", (0.19, 0.21), "pct",
     False, "≈ 95 %", "≈ 88–90 %"),
    ("Efficiency at pT 0.4–0.5 GeV", "efficiency_vs_pt", (0.4, 0.5), "pct",
     False, "≈ 98 %", "≈ 97 %"),
    ("Efficiency at θ 8–10° (pT > 1 GeV)", "efficiency_vs_theta", (8.0, 10.0),
     "pct", True, "≈ 97 %", "≈ 92–96 %"),
    ("Efficiency at θ 12–20° (pT > 1 GeV)", "efficiency_vs_theta",
     (12.0, 20.0), "pct", True, "≈ 98.5–99 %", "≈ 98–99 %"),
    ("Efficiency at θ 20–90° (pT > 1 GeV)", "efficiency_vs_theta",
     (20.0, 90.0), "pct", True, "≈ 99.7–100 %", "≈ 99.7–100 %"),
    ("Efficiency at R_vtx < 40 mm (pT > 1 GeV, 10–170°, ΔR > 0.02)",
     "efficiency_vs_vertex_radius", (0.0, 40.0), "pct", False, "≈ 99–100 %",
     "≈ 99–100 %"),
    ("Efficiency at R_vtx 50–180 mm", "efficiency_vs_vertex_radius",
     (50.0, 180.0), "pct", False, "≈ 73 %", "≈ 68 %"),
    ("Efficiency at R_vtx ≈ 250 mm", "efficiency_vs_vertex_radius",
     (240.0, 260.0), "pct", False, "≈ 60 %", "≈ 60 %"),
    ("Efficiency at R_vtx 350–500 mm", "efficiency_vs_vertex_radius",
     (350.0, 500.0), "pct", False, "≈ 10 %", "≈ 10 %"),
    ("Fake rate at pT 0.1–0.5 GeV (10° < θ < 170°)", "fake_rate_vs_pt",
     (0.1, 0.5), "sci", False, "≈ 2–3 × 10⁻³", "≈ 7–8 × 10⁻³"),
    ("Fake rate at pT ≈ 1 GeV", "fake_rate_vs_pt", (0.95, 1.05), "sci",
     False, "≈ 4–5 × 10⁻³", "≈ 7 × 10⁻³"),
    ("Fake rate at pT ≈ 10 GeV", "fake_rate_vs_pt", (9.5, 10.5), "sci",
     False, "≈ 1 × 10⁻²", "≈ 1 × 10⁻²"),
    ("Fake rate at pT ≈ 100 GeV", "fake_rate_vs_pt", (95.0, 105.0), "sci",
     False, "≈ 3 × 10⁻²", "≈ 3 × 10⁻²"),
    ("Fake rate at pT 200–250 GeV", "fake_rate_vs_pt", (200.0, 250.0), "sci",
     False, "≈ 5–6 × 10⁻²", "≈ 5–6 × 10⁻²"),
    ("Fake rate versus θ (pT > 1 GeV), all θ", "fake_rate_vs_theta",
     (0.0, 180.0), "sci", False, "≈ 0.5–2 × 10⁻² (flat)", "same"),
    ("Duplicate rate at pT ≈ 0.1 GeV (CLICdp, both tracks counted)*",
     "duplicate_rate_vs_pt", (0.1, 0.11), "pct", False, "≈ 30 %", "≈ 30 %"),
    ("Duplicate rate at pT ≈ 1 GeV*", "duplicate_rate_vs_pt", (0.95, 1.05),
     "pct", False, "≈ 2–3 %", "≈ 6 %"),
    ("Duplicate rate at pT ≈ 3 GeV*", "duplicate_rate_vs_pt", (2.8, 3.2),
     "pct", False, "≈ 5 %", "≈ 5 %"),
    ("Duplicate rate above 30 GeV*", "duplicate_rate_vs_pt", (30.0, 1e9),
     "pct", False, "≈ 10 %", "≈ 10 %"),
]
TTBAR_NOTES = [
    "CLICdp numbers: evaluation.md B2 (CLICdp validation plots, "
    "ILCSoft-2019-09-04 and -2020-02-07, CLIC_o3_v14), approximate readings.",
    "B1 (paper): fully efficient for pT > 1 GeV, still well above 90 % down "
    "to pT ≈ 200 MeV; efficiency and fake rate almost unaffected by 30 BX of "
    "γγ → hadrons; at most 1 % loss for Δ_MC < 0.02 rad.",
    "* CLICdp duplicate rates were measured before split-track merging was "
    "enabled.",
]
# Points drawn on the plots (x, value), per background condition.
TTBAR_PLOT_REFERENCE = {
    "efficiency_vs_pt": {
        False: [(0.1, 0.925), (0.2, 0.95), (0.45, 0.98), (1.0, 0.997),
                (10.0, 0.998), (100.0, 0.998), (250.0, 0.998)],
        True: [(0.1, 0.82), (0.2, 0.89), (0.45, 0.97), (1.0, 0.995),
               (10.0, 0.997), (100.0, 0.997), (250.0, 0.997)],
    },
    "efficiency_vs_theta": {
        False: [(9.0, 0.97), (16.0, 0.988), (30.0, 0.998), (60.0, 0.999),
                (90.0, 0.999), (171.0, 0.97), (164.0, 0.988)],
        True: [(9.0, 0.94), (16.0, 0.985), (30.0, 0.998), (60.0, 0.999),
               (90.0, 0.999), (171.0, 0.94), (164.0, 0.985)],
    },
    "efficiency_vs_vertex_radius": {
        False: [(20.0, 0.995), (115.0, 0.73), (250.0, 0.60), (330.0, 0.55),
                (340.0, 0.20), (425.0, 0.10), (575.0, 0.05)],
        True: [(20.0, 0.995), (115.0, 0.68), (250.0, 0.60), (330.0, 0.55),
               (340.0, 0.20), (425.0, 0.10), (575.0, 0.05)],
    },
    "fake_rate_vs_pt": {
        False: [(0.3, 2.5e-3), (1.0, 4.5e-3), (10.0, 1e-2), (100.0, 3e-2),
                (225.0, 5.5e-2)],
        True: [(0.3, 7.5e-3), (1.0, 7e-3), (10.0, 1e-2), (100.0, 3e-2),
               (225.0, 5.5e-2)],
    },
    "duplicate_rate_vs_pt": {
        False: [(0.1, 0.3), (1.0, 0.025), (3.0, 0.05), (50.0, 0.10)],
        True: [(0.1, 0.3), (1.0, 0.06), (3.0, 0.05), (50.0, 0.10)],
    },
}

# B1/B2/B3 for single muons.
MUON_REFERENCE = [
    ("Efficiency (all)", "summary:efficiency.all", "pct",
     "≈ 100 % (fully efficient in the acceptance)"),
    ("Efficiency at pT ≥ 0.3 GeV", "efficiency_vs_pt_all:0.3:1e9", "pct",
     "≥ 99.9 % at θ = 10°, 30°, 89°"),
    ("Fake rate", "summary:fake_rate", "sci", "negligible"),
]

# B5: ideal-resolution estimate from the layouts (muon from the origin).
# theta [deg] -> sigma(pT)/pT^2 [1/GeV] and sigma(d0) [um] at p = 1, 10,
# 100, 1000 GeV.
ANCHOR_P = [1.0, 10.0, 100.0, 1000.0]
ANCHORS = {
    "CLICdet": {
        10: ([6.7e-2, 5.3e-3, 6.3e-4, 2.9e-4], [259, 29, 5.2, 3.4]),
        20: ([1.7e-2, 1.5e-3, 1.7e-4, 5.6e-5], [114, 14.7, 3.1, 1.9]),
        30: ([7.5e-3, 6.3e-4, 7.1e-5, 2.4e-5], [67, 9.3, 2.5, 1.6]),
        50: ([2.9e-3, 2.9e-4, 3.7e-5, 1.8e-5], [37, 6.0, 1.8, 1.5]),
        70: ([1.7e-3, 2.1e-4, 3.0e-5, 1.8e-5], [27, 5.0, 1.7, 1.5]),
        89: ([1.6e-3, 1.9e-4, 2.8e-5, 1.8e-5], [25, 4.7, 1.7, 1.5]),
    },
    "CLD": {
        10: ([1.3e-1, 9.8e-3, 1.2e-3, 4.6e-4], [196, 22.5, 3.3, 2.0]),
        30: ([1.4e-2, 1.3e-3, 1.5e-4, 4.3e-5], [43, 5.4, 2.0, 1.4]),
        50: ([4.7e-3, 4.8e-4, 5.7e-5, 2.2e-5], [23, 3.7, 1.6, 1.4]),
        70: ([2.6e-3, 2.8e-4, 3.6e-5, 1.7e-5], [17, 3.2, 1.5, 1.3]),
        89: ([2.4e-3, 2.5e-4, 3.4e-5, 1.7e-5], [15, 3.1, 1.5, 1.3]),
    },
}
PT_REQUIREMENT = 2e-5  # B3: sigma(pT)/pT^2 for high-momentum central tracks

# File name -> (x label, log x, y label, log y, title).
RATIO_PLOTS = {
    "efficiency_vs_pt": ("true pT [GeV]", True, "efficiency", False,
                         "Efficiency vs pT (10° < θ < 170°, R_vtx < 50 mm, ΔR > 0.02)"),
    "efficiency_vs_pt_all": ("true pT [GeV]", True, "efficiency", False,
                             "Efficiency vs pT (all reconstructable particles)"),
    "efficiency_vs_theta": ("true θ [deg]", False, "efficiency", False,
                            "Efficiency vs θ (pT > 1 GeV, R_vtx < 50 mm, ΔR > 0.02)"),
    "efficiency_vs_phi": ("true φ [deg]", False, "efficiency", False,
                          "Efficiency vs φ (pT > 1 GeV, 10° < θ < 170°, R_vtx < 50 mm, ΔR > 0.02)"),
    "efficiency_vs_vertex_radius": ("production radius [mm]", False,
                                    "efficiency", False,
                                    "Efficiency vs R_vtx (pT > 1 GeV, 10° < θ < 170°, ΔR > 0.02)"),
    "efficiency_vs_proximity": ("proximity ΔR to the closest particle", True,
                                "efficiency", False,
                                "Efficiency vs proximity (pT > 1 GeV, 10° < θ < 170°, R_vtx < 50 mm)"),
    "fake_rate_vs_pt": ("reconstructed pT [GeV]", True, "fake rate", True,
                        "Fake rate vs pT (10° < θ < 170°, nHits ≥ min)"),
    "fake_rate_vs_theta": ("reconstructed θ [deg]", False, "fake rate", True,
                           "Fake rate vs θ (pT > 1 GeV, nHits ≥ min)"),
    "duplicate_rate_vs_pt": ("reconstructed pT [GeV]", True,
                             "duplicate rate (CLICdp)", True,
                             "Duplicate rate vs pT (10° < θ < 170°, nHits ≥ min)"),
    "duplicate_rate_vs_theta": ("reconstructed θ [deg]", False,
                                "duplicate rate (CLICdp)", True,
                                "Duplicate rate vs θ (pT > 1 GeV, nHits ≥ min)"),
}

RESOLUTION_LABELS = {
    "d0": "σ(d0) [µm]",
    "z0": "σ(z0) [µm]",
    "phi0": "σ(φ0) [mrad]",
    "theta": "σ(θ) [mrad]",
    "pt": "σ(pT) [GeV]",
    "pt_over_pt2": "σ(pT)/pT² [GeV⁻¹]",
}


# ---------------------------------------------------------------------------
# Reading.

def to_number(text):
    try:
        return float(text)
    except ValueError:
        return text


def read_csv(path):
    """Rows of a CSV file as dicts, numbers converted ('nan' -> nan)."""
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        return [{k: to_number(v) for k, v in row.items()}
                for row in csv.DictReader(f)]


def is_finite(x):
    return isinstance(x, float) and math.isfinite(x)


def ratio_in_range(rows, lo, hi, fold=False):
    """Sums numerator and denominator of the bins overlapping [lo, hi]
    (and its mirror 180 - x for a folded theta range)."""
    if not rows:
        return 0, 0
    ranges = [(lo, hi)]
    if fold:
        ranges.append((180.0 - hi, 180.0 - lo))
    num = den = 0
    for r in rows:
        # Overlap, with a relative margin against edges written rounded.
        if any(r["low"] < b - 1e-9 * abs(b) and r["high"] > a + 1e-9 * abs(a)
               for a, b in ranges):
            num += int(r["numerator"])
            den += int(r["denominator"])
    return num, den


def format_ratio(num, den, kind):
    if den == 0:
        return "—"
    p = num / den
    err = math.sqrt(p * (1 - p) / den)
    if kind == "pct":
        return f"{100 * p:.2f} ± {100 * err:.2f} % ({num}/{den})"
    return f"{p:.2e} ± {err:.1e} ({num}/{den})"


def format_value(x, kind):
    if x is None or not is_finite(float(x)):
        return "—"
    return f"{100 * x:.2f} %" if kind == "pct" else f"{x:.2e}"


def detector_key(name):
    n = (name or "").lower()
    if n.startswith("clicdet") or n.startswith("clic"):
        return "CLICdet"
    if n.startswith("cld"):
        return "CLD"
    return None


def is_ttbar(summary):
    return "ttbar" in str(summary.get("sample", "")).lower()


def is_single_particle(summary):
    return bool(summary.get("definitions", {}).get("single_particle")) or \
        "pulls" in summary


# ---------------------------------------------------------------------------
# Plots (matplotlib).

def bin_centres(rows, log):
    xs = []
    for r in rows:
        if log and r["low"] > 0:
            xs.append(math.sqrt(r["low"] * r["high"]))
        else:
            xs.append(0.5 * (r["low"] + r["high"]))
    return xs


def plot_ratio(plt, folder, name, spec, summary, with_background):
    rows = read_csv(os.path.join(folder, name + ".csv"))
    if rows is None:
        return None
    xlabel, logx, ylabel, logy, title = spec
    used = [r for r in rows if r["denominator"] > 0]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    shown = []  # y values that the axis range must include
    if used:
        xs = bin_centres(used, logx)
        ys = [r["value"] for r in used]
        xerr = [[x - r["low"] for x, r in zip(xs, used)],
                [r["high"] - x for x, r in zip(xs, used)]]
        yerr = [[max(0.0, y - r["lower"]) for y, r in zip(ys, used)],
                [max(0.0, r["upper"] - y) for y, r in zip(ys, used)]]
        ax.errorbar(xs, ys, xerr=xerr, yerr=yerr, fmt="o", ms=3,
                    color="C0", label="conftrack")
        shown += ys
        if not logy:
            shown += [r["lower"] for r in used if is_finite(r["lower"])]
    else:
        ax.text(0.5, 0.5, "no entries", transform=ax.transAxes, ha="center")
    ref = TTBAR_PLOT_REFERENCE.get(name) if is_ttbar(summary) else None
    if ref:
        pts = ref[with_background]
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "s", mfc="none",
                color="0.4", label="CLICdp validation (approx.)")
        shown += [p[1] for p in pts]
    if logy:
        # Zero rates cannot be drawn on a log axis; the CSV has them.
        positive = [y for y in shown if y > 0]
        if positive:
            ax.set_yscale("log")
            ax.set_ylim(min(positive) / 3, min(1.5, max(positive) * 3))
    elif shown:
        ax.set_ylim(max(0.0, min(shown + [0.9]) - 0.05), 1.02)
    if logx:
        ax.set_xscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    png = name + ".png"
    fig.savefig(os.path.join(folder, png), dpi=100)
    plt.close(fig)
    return png


def plot_resolutions(plt, folder, summary):
    rows = read_csv(os.path.join(folder, "resolutions.csv"))
    if not rows:
        return []
    anchors = ANCHORS.get(detector_key(summary.get("detector")))
    pngs = []
    for quantity, label in RESOLUTION_LABELS.items():
        points = [r for r in rows if r["quantity"] == quantity and
                  is_finite(r["sigma"]) and r["sigma"] > 0]
        if not points:
            continue
        fig, ax = plt.subplots(figsize=(7, 4.5))
        thetas = sorted({r["theta_deg"] for r in points})
        for i, theta in enumerate(thetas):
            pts = sorted((r for r in points if r["theta_deg"] == theta),
                         key=lambda r: r["pt_mean_GeV"])
            color = f"C{i % 10}"
            ax.errorbar([r["pt_mean_GeV"] for r in pts],
                        [r["sigma"] for r in pts],
                        yerr=[r["sigma_error"] for r in pts], fmt="o-", ms=4,
                        color=color, label=f"θ = {theta:g}°")
            anchor = anchors.get(int(round(theta))) if anchors else None
            if anchor and quantity in ("pt_over_pt2", "d0"):
                values = anchor[0] if quantity == "pt_over_pt2" else anchor[1]
                sin_t = math.sin(math.radians(theta))
                ax.plot([p * sin_t for p in ANCHOR_P], values, "--",
                        color=color, alpha=0.7)
        if anchors and quantity in ("pt_over_pt2", "d0"):
            ax.plot([], [], "--", color="0.4",
                    label=f"ideal fit, {detector_key(summary.get('detector'))}"
                          " (evaluation.md B5)")
        if quantity == "pt_over_pt2":
            ax.axhline(PT_REQUIREMENT, color="0.5", ls=":",
                       label="CLIC requirement 2×10⁻⁵ GeV⁻¹")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("true pT [GeV]")
        ax.set_ylabel(label)
        ax.set_title(f"Resolution: {label} vs pT (Gaussian core fit)",
                     fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        png = f"resolution_{quantity}.png"
        fig.savefig(os.path.join(folder, png), dpi=100)
        plt.close(fig)
        pngs.append(png)
    return pngs


def plot_pulls(plt, np, folder):
    fits = read_csv(os.path.join(folder, "pulls.csv"))
    if not fits:
        return None
    fig, axes = plt.subplots(2, 4, figsize=(14, 6.5))
    for ax, fit in zip(axes.flat, fits):
        rows = read_csv(os.path.join(folder, f"pull_{fit['quantity']}.csv"))
        if not rows:
            ax.set_visible(False)
            continue
        lows = np.array([r["low"] for r in rows])
        highs = np.array([r["high"] for r in rows])
        counts = np.array([r["count"] for r in rows])
        ax.stairs(counts, np.append(lows, highs[-1]), fill=True, alpha=0.5)
        mean, width = fit["mean"], fit["width"]
        if is_finite(mean) and is_finite(width) and width > 0:
            x = np.linspace(lows[0], highs[-1], 300)
            n = fit["entries"] * (highs[0] - lows[0])
            ax.plot(x, n / (width * math.sqrt(2 * math.pi)) *
                    np.exp(-0.5 * ((x - mean) / width) ** 2), "r-")
        ax.set_title(f"pull {fit['quantity']}: mean {mean:.3f}, "
                     f"width {width:.3f}", fontsize=9)
        ax.set_xlabel("(reco − true) / σ")
    for ax in list(axes.flat)[len(fits):]:
        ax.set_visible(False)
    fig.tight_layout()
    fig.savefig(os.path.join(folder, "pulls.png"), dpi=90)
    plt.close(fig)
    return "pulls.png"


def plot_times(plt, folder, summary):
    pngs = []
    steps = read_csv(os.path.join(folder, "time_steps.csv")) or []
    times = summary.get("time_ms_per_event", {})
    labels = [f"finding: {s['step']}" for s in steps]
    values = [s["ms_per_event"] for s in steps]
    for key in ("fitting", "simulation"):
        if is_finite(float(times.get(key, float("nan")))):
            labels.append(key)
            values.append(times[key])
    if labels:
        fig, ax = plt.subplots(figsize=(7, 0.5 * len(labels) + 1.5))
        colors = ["C0"] * len(steps) + ["C1", "C7"][:len(labels) - len(steps)]
        ax.barh(range(len(labels)), values, color=colors)
        ax.set_yticks(range(len(labels)))
        ax.set_yticklabels(labels, fontsize=8)
        ax.invert_yaxis()
        ax.set_xlabel("time per event [ms]")
        ax.set_title(f"CPU time per step (reconstruction "
                     f"{times.get('reconstruction', 0):.1f} ms/event)",
                     fontsize=9)
        ax.grid(True, axis="x", alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(folder, "time_steps.png"), dpi=100)
        plt.close(fig)
        pngs.append("time_steps.png")
    rows = read_csv(os.path.join(folder, "time_per_event.csv"))
    if rows and any(r["count"] > 0 for r in rows):
        fig, ax = plt.subplots(figsize=(7, 4))
        edges = [r["low"] for r in rows] + [rows[-1]["high"]]
        ax.stairs([r["count"] for r in rows], edges, fill=True, alpha=0.6)
        ax.set_xscale("log")
        used = [r for r in rows if r["count"] > 0]
        ax.set_xlim(used[0]["low"] / 2, used[-1]["high"] * 2)
        ax.set_xlabel("reconstruction time per event (finding + fitting) [ms]")
        ax.set_ylabel("events")
        ax.set_title("Reconstruction time per event", fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(folder, "time_per_event.png"), dpi=100)
        plt.close(fig)
        pngs.append("time_per_event.png")
    return pngs


def make_plots(folder, summary):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    with_background = int(summary.get("overlay_bx", 0) or 0) > 0
    pngs = []
    for name, spec in RATIO_PLOTS.items():
        png = plot_ratio(plt, folder, name, spec, summary, with_background)
        if png:
            pngs.append(png)
    pngs += plot_resolutions(plt, folder, summary)
    png = plot_pulls(plt, np, folder)
    if png:
        pngs.append(png)
    pngs += plot_times(plt, folder, summary)
    # The event display, when conftrack drew one (conftrack_display.py).
    if os.path.exists(os.path.join(folder, "event_display.png")):
        pngs.append("event_display.png")
    return pngs


# ---------------------------------------------------------------------------
# HTML.

def get_path(summary, dotted):
    value = summary
    for key in dotted.split("."):
        if not isinstance(value, dict) or key not in value:
            return None
        value = value[key]
    return value


def summary_rows(summary):
    counts = summary.get("counts", {})

    def ratio(key, kind="pct"):
        c = counts.get(key)
        if not c:
            return "—"
        return format_ratio(int(c["passed"]), int(c["total"]), kind)

    times = summary.get("time_ms_per_event", {})
    rows = [
        ("Sample", f"{summary.get('sample', '?')}"
                   + (f" + {summary.get('overlay_bx')} BX overlay"
                      if summary.get("overlay_bx") else "")),
        ("Detector", f"{summary.get('detector', '?')} "
                     f"(Bz = {summary.get('bz_T', float('nan'))} T)"),
        ("Events", f"{summary.get('events')} (seed {summary.get('seed')}, "
                   f"{summary.get('threads')} threads, conftrack "
                   f"{summary.get('version')})"),
        ("Reconstructable particles", summary.get("reconstructable_particles")),
        ("Reconstructed tracks", f"{summary.get('reconstructed_tracks')} "
                                 f"(fitted {summary.get('fitted_tracks')})"),
        ("Efficiency (all)", ratio("efficiency_all")),
        ("Efficiency pT > 1 GeV", ratio("efficiency_pt_above_1GeV")),
        ("Efficiency 0.1 ≤ pT ≤ 1 GeV", ratio("efficiency_pt_0p1_to_1GeV")),
        ("Efficiency, signal particles", ratio("efficiency_signal")),
        ("Efficiency, background particles", ratio("efficiency_background")),
        ("Efficiency, CLICdp cuts of the θ plot", ratio("efficiency_theta_plot_cuts")),
        ("Efficiency, CLICdp cuts of the pT plot", ratio("efficiency_pt_plot_cuts")),
        ("Fake rate (all tracks)", ratio("fake_rate", "sci")),
        ("Duplicate rate (CLICdp, all tracks)", ratio("duplicate_rate")),
        ("Fake / duplicate rate, nHits ≥ min",
         f"{ratio('fake_rate_selected', 'sci')} / "
         f"{ratio('duplicate_rate_selected')}"),
        ("ACTS efficiency / fake / duplicate (50 %, double matching)",
         f"{ratio('acts_efficiency')} / {ratio('acts_fake_rate', 'sci')} / "
         f"{ratio('acts_duplicate_rate')}"),
        ("Time per event [ms]",
         f"simulation {times.get('simulation', 0):.1f}, finding "
         f"{times.get('finding', 0):.1f}, fitting {times.get('fitting', 0):.1f}"
         f", reconstruction {times.get('reconstruction', 0):.1f}"),
        ("Peak RSS", f"{summary.get('peak_rss_mb') or float('nan'):.1f} MiB"),
    ]
    for name, fit in (summary.get("pulls") or {}).items():
        rows.append((f"Pull {name}", f"mean {fit['mean']:.3f} ± "
                     f"{fit['mean_error']:.3f}, width {fit['width']:.3f} ± "
                     f"{fit['width_error']:.3f} ({fit['entries']} tracks)"))
    return rows


def reference_rows(folder, summary):
    """(label, ours, reference columns...) and the column headers."""
    if is_ttbar(summary):
        cache = {}
        rows = []
        for label, name, (lo, hi), kind, fold, ref0, ref1 in TTBAR_REFERENCE:
            if name not in cache:
                cache[name] = read_csv(os.path.join(folder, name + ".csv"))
            num, den = ratio_in_range(cache[name], lo, hi, fold)
            rows.append((label, format_ratio(num, den, kind), ref0, ref1))
        return (["Quantity", "conftrack", "CLICdp, no background",
                 "CLICdp, 30 BX γγ → hadrons"], rows, TTBAR_NOTES)
    if is_single_particle(summary):
        rows = []
        for label, source, kind, ref in MUON_REFERENCE:
            if source.startswith("summary:"):
                ours = format_value(get_path(summary, source[8:]), kind)
            else:
                name, lo, hi = source.split(":")
                num, den = ratio_in_range(
                    read_csv(os.path.join(folder, name + ".csv")), float(lo),
                    float(hi))
                ours = format_ratio(num, den, kind)
            rows.append((label, ours, ref))
        res = [r for r in (summary.get("resolutions") or [])
               if r["quantity"] == "pt_over_pt2" and r["theta_deg"] >= 80
               and r.get("sigma") is not None]
        if res:
            best = max(res, key=lambda r: r["pt_GeV"])
            rows.append((f"σ(pT)/pT² at θ = {best['theta_deg']:g}°, "
                         f"pT = {best['pt_GeV']:.3g} GeV",
                         f"{best['sigma']:.2e} GeV⁻¹",
                         "≤ 2 × 10⁻⁵ GeV⁻¹ (requirement, B3) for high "
                         "momentum; ideal fit 1.8 × 10⁻⁵ (CLICdet, B5)"))
        return (["Quantity", "conftrack", "CLICdp / reference"], rows,
                ["References: evaluation.md B1, B2 (single µ), B3, B5."])
    return None


def write_html(folder, summary, pngs, have_plots):
    csvs = sorted(f for f in os.listdir(folder) if f.endswith(".csv"))
    e = html.escape
    out = ["<!DOCTYPE html>", "<html><head><meta charset=\"utf-8\">",
           f"<title>conftrack performance: {e(str(summary.get('sample', '')))}"
           "</title>",
           "<style>body{font-family:sans-serif;margin:2em;max-width:1500px}"
           "table{border-collapse:collapse;margin-bottom:1em}"
           "td,th{border:1px solid #ccc;padding:3px 10px;text-align:left}"
           "th{background:#f0f0f0}.plots img{width:48%;margin:0.5%}"
           ".note{color:#555;font-size:90%}</style></head><body>",
           f"<h1>conftrack performance: {e(str(summary.get('sample', '')))}"
           f" on {e(str(summary.get('detector', '')))}</h1>",
           "<h2>Summary</h2>", "<table>"]
    for label, value in summary_rows(summary):
        out.append(f"<tr><th>{e(str(label))}</th><td>{e(str(value))}</td></tr>")
    out.append("</table>")
    defs = summary.get("definitions", {})
    if defs:
        out.append(f"<p class=\"note\">Definitions: reconstructable = "
                   f"{e(str(defs.get('reconstructable')))}; matching "
                   f"{e(str(defs.get('matching')))}, purity ≥ "
                   f"{defs.get('purity')}; plots and “nHits ≥ min” use "
                   f"nHits ≥ {defs.get('min_track_hits')} (evaluation.md A1)."
                   "</p>")
    ref = reference_rows(folder, summary)
    if ref:
        headers, rows, notes = ref
        out.append("<h2>Comparison with the reference numbers</h2><table>")
        out.append("<tr>" + "".join(f"<th>{e(h)}</th>" for h in headers)
                   + "</tr>")
        for row in rows:
            out.append("<tr>" + "".join(f"<td>{e(str(c))}</td>" for c in row)
                       + "</tr>")
        out.append("</table>")
        for note in notes:
            out.append(f"<p class=\"note\">{e(note)}</p>")
    out.append("<h2>Plots</h2>")
    if have_plots:
        out.append("<div class=\"plots\">")
        for png in pngs:
            out.append(f"<a href=\"{e(png)}\"><img src=\"{e(png)}\" "
                       f"alt=\"{e(png)}\"></a>")
        out.append("</div>")
    else:
        out.append(f"<p>No plots: matplotlib and numpy are missing "
                   f"(install them with <code>{e(INSTALL_HINT)}</code> and "
                   f"run <code>python3 scripts/conftrack_plots.py "
                   f"{e(folder)}</code>).</p>")
    out.append("<h2>Files</h2><ul>")
    out.append("<li><a href=\"summary.json\">summary.json</a></li>")
    for f in csvs:
        out.append(f"<li><a href=\"{e(f)}\">{e(f)}</a></li>")
    out.append("</ul></body></html>")
    with open(os.path.join(folder, "index.html"), "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    folder = argv[1]
    summary_file = os.path.join(folder, "summary.json")
    if not os.path.isfile(summary_file):
        print(f"conftrack_plots: {summary_file}: no such file", file=sys.stderr)
        return 2
    with open(summary_file, encoding="utf-8") as f:
        summary = json.load(f)
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError:
        write_html(folder, summary, [], False)
        print(f"conftrack_plots: matplotlib/numpy missing: no plots; install "
              f"them with: {INSTALL_HINT}", file=sys.stderr)
        return MISSING_MATPLOTLIB_EXIT
    pngs = make_plots(folder, summary)
    write_html(folder, summary, pngs, True)
    print(f"conftrack_plots: {len(pngs)} plots and index.html in {folder}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
