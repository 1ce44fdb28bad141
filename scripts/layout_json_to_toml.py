#!/usr/bin/env python3
"""Generates detectors/clicdet.toml and detectors/cld.toml from the layout
JSON files in data/layouts/ (a developer tool; the TOML files are shipped
and are what conftrack reads).

Usage: scripts/layout_json_to_toml.py data/layouts/clicdet_layout.json.gz \
           clicdet > detectors/clicdet.toml
"""
import gzip
import json
import sys

SUBDETECTORS = [  # (name, kind, JSON subdetector key, trackml volume(s))
    ("VertexBarrel", "barrel", "VertexBarrel", 1),
    ("VertexEndcap", "endcap", "VertexEndcap", (2, 3)),
    ("InnerTrackerBarrel", "barrel", "InnerTrackerBarrel", 4),
    ("InnerTrackerEndcap", "endcap", "InnerTrackerEndcap", (5, 6)),
    ("OuterTrackerBarrel", "barrel", "OuterTrackerBarrel", 7),
    ("OuterTrackerEndcap", "endcap", "OuterTrackerEndcap", (8, 9)),
]


def fmt(x):
    return repr(float(x))


def main(path, short):
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        d = json.load(f)
    src = "data/layouts/" + path.split("/")[-1]
    out = []
    w = out.append
    w(f"# {d['detector']} tracker, model {d['model']}: conftrack detector file.")
    w(f"# Generated from {src} by scripts/layout_json_to_toml.py; values from")
    w("# detectors.md. Units are in the key names (_mm, _um, _T); x_over_x0 is the")
    w("# material at normal incidence as a fraction of X0 (module + support).")
    w("# Approximations (docs/algorithm.md, 'Detector model'): barrel layers are cylinders at")
    w("# the sensor mid-plane radius (flat staves, staggered modules and module")
    w("# overlaps ignored); disks are flat at their nominal z (the CLICdet")
    w("# vertex-endcap spiral petals at the mean petal z); module ids use equal")
    w("# phi sectors and equal-width z slices / radial rings.")
    w("")
    w("[detector]")
    w(f'name = "{d["detector"]}"')
    w(f'model = "{d["model"]}"')
    w(f"bz_T = {fmt(d['field_T'])}")
    env = {"clicdet": (1500.0, 2306.0), "cld": (2145.0, 2300.0)}[short]
    w(f"envelope_r_mm = {fmt(env[0])}")
    w(f"envelope_z_mm = {fmt(env[1])}")
    for name, kind, key, vol in SUBDETECTORS:
        w("")
        w("[[subdetector]]")
        w(f'name = "{name}"')
        w(f'kind = "{kind}"')
        if kind == "barrel":
            w(f"trackml_volume = {vol}")
            for l in d["barrel_layers"]:
                if l["subdetector"] != key:
                    continue
                w("")
                w("  [[subdetector.layer]]")
                w(f'  name = "{l["name"]}"')
                w(f"  r_mm = {fmt(l['r_mm'])}")
                w(f"  half_z_mm = {fmt(l['half_z_mm'])}")
                w(f"  x_over_x0 = {fmt(l['thickness_X0'])}")
                w(f"  sigma_rphi_um = {fmt(l['resolution_rphi_um'])}")
                w(f"  sigma_z_um = {fmt(l['resolution_z_um'])}")
                w(f"  n_phi_modules = {l.get('n_phi_modules', l.get('n_staves', 1))}")
                w(f"  n_z_modules = {l.get('n_z_modules', 1)}")
        else:
            w(f"trackml_volumes = [{vol[0]}, {vol[1]}]  # -z, +z")
            for l in d["endcap_disks"]:
                if l["subdetector"] != key:
                    continue
                rings = l.get("rings", [])
                w("")
                w("  [[subdetector.layer]]")
                w(f'  name = "{l["name"]}"')
                w(f"  z_mm = {fmt(l['z_mm'])}")
                w(f"  r_min_mm = {fmt(l['r_min_mm'])}")
                w(f"  r_max_mm = {fmt(l['r_max_mm'])}")
                w(f"  x_over_x0 = {fmt(l['thickness_X0'])}")
                w(f"  sigma_rphi_um = {fmt(l['resolution_rphi_um'])}")
                w(f"  sigma_r_um = {fmt(l['resolution_r_um'])}")
                nphi = rings[0]["n_modules"] if rings else l.get("n_petals", 1)
                w(f"  n_phi_modules = {nphi}")
                w(f"  n_rings = {max(1, len(rings))}")
    w("")
    w("# Passive material that matters for multiple scattering (detectors.md).")
    w("[passive]")
    bp = d["beampipe"]
    w("")
    w("[[passive.cylinder]]")
    w('name = "BeamPipe"')
    w(f"r_mm = {fmt(0.5 * (bp['r_inner_mm'] + bp['r_outer_mm']))}")
    w(f"z_max_mm = {fmt(bp['half_z_mm'])}")
    w(f"x_over_x0 = {fmt(bp['thickness_X0'])}")
    for c in d["passive_cylinders"]:
        w("")
        w("[[passive.cylinder]]")
        w(f'name = "{c["name"].split(" (")[0].replace(" ", "_")}"')
        w(f"r_mm = {fmt(c['r_mm'])}")
        if "z_min_mm" in c:
            w(f"z_min_mm = {fmt(c['z_min_mm'])}")
        w(f"z_max_mm = {fmt(c['z_max_mm'])}")
        w(f"x_over_x0 = {fmt(c['thickness_X0'])}")
    for c in d["passive_disks"]:
        w("")
        w("[[passive.disk]]")
        w(f'name = "{c["name"].split(" (")[0].replace(" ", "_")}"')
        w(f"z_mm = {fmt(c['z_mm'])}")
        w(f"r_min_mm = {fmt(c['r_min_mm'])}")
        w(f"r_max_mm = {fmt(c['r_max_mm'])}")
        w(f"x_over_x0 = {fmt(c['thickness_X0'])}")
    for c in d.get("passive_cones", []):
        w("")
        w("[[passive.cone]]")
        w(f'name = "{c["name"].split(" (")[0].replace(" ", "_")}"')
        w(f"z1_mm = {fmt(c['z1_mm'])}")
        w(f"r1_mm = {fmt(c['r1_mm'])}")
        w(f"z2_mm = {fmt(c['z2_mm'])}")
        w(f"r2_mm = {fmt(c['r2_mm'])}")
        w(f"x_over_x0 = {fmt(c['thickness_X0_normal'])}")
    if short == "clicdet":
        # The steel beam-pipe cone (detectors.md 1.1): 4.4 mm iron, X0 17.58 mm.
        w("")
        w("# Steel beam-pipe cone (detectors.md 1.1, 'Beam pipe, beyond'): 4.4 mm of")
        w("# iron (X0 = 17.58 mm); only tracks below about 6.5 degrees cross it.")
        w("[[passive.cone]]")
        w('name = "BeamPipeCone"')
        w("z1_mm = 337.0")
        w("r1_mm = 31.4")
        w("z2_mm = 2080.0")
        w("r2_mm = 237.6")
        w(f"x_over_x0 = {fmt(round(4.4 / 17.58, 4))}")
    print("\n".join(out))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
