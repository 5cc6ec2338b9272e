#!/usr/bin/env python3
"""Read range of a half-wave dipole tag against its distance to a surface behind it (docs/tag-antenna.md).

For each distance d the tag faces the reader across free space with a metal plate (or a half-space of water, or
of any dielectric: --backing) d behind it, as `rfidray link --tag-backing MATERIAL:D` models it (an infinite
plane: its image path and the antenna's detuning). Three curves:
  - rfidray without the tag model: the point tag, the surface as an image path only (|1 + Γ e^{-j2kd}|²);
  - rfidray with the tag model (--tag-antenna dipole, chip matched in free space), forward- and reverse-limited;
  - NEC-2 (nec2c, when installed): a plane wave at normal incidence into the dipole over a perfect ground (GN 1)
    or NEC-2's Sommerfeld ground of the same ε and σ (GN 2), loaded by the chip, against the same in free space
    (forward link).
The read range is where the chip's power falls to its sensitivity (forward) or the backscatter to the reader's
(reverse), from one link at a reference distance: both scale as 1/r² and 1/r⁴ along the normal.

Usage: python3 bench/tag_on_metal.py RFIDRAY_BINARY OUT_DIR [--backing metal|water|dielectric:EPS_R:SIGMA_S_M]
                                   [--png FILE]
Writes OUT_DIR/tag_on_NAME.csv and OUT_DIR/tag_on_NAME.log (NAME: metal, water, ...); the chart to --png (default
OUT_DIR/tag_on_NAME.png).
Exit 2 on bad arguments or when rfidray fails.
"""
import argparse
import cmath
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

FREQUENCY_HZ = 866e6
LENGTH_M, RADIUS_M = 0.166, 0.0005
REFERENCE_M = 3.0  # reader-tag distance of the reference link
DISTANCES_M = [0.002, 0.003, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.03, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3]
NEC_DISTANCES_M = [0.003, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2]


def fail(msg):
    print(f"tag_on_metal.py: {msg}", file=sys.stderr)
    sys.exit(2)


def link(binary, scene, extra):
    cmd = [binary, "link", "--scene", scene, "--material", "metal", "--antenna", f"{-REFERENCE_M},0,0", "--tag", "0,0,0", "--tag-rpy",
           "0,0,180", "--frequency", str(FREQUENCY_HZ), "--json"] + extra
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
    return json.loads(r.stdout)


def ranges(j, key):
    """Forward- and reverse-limited read range (m) from a link at REFERENCE_M."""
    c = j[key]
    reader = j["reader"]
    if c["tag_power_dbm"] is None:
        return 0.0, 0.0
    forward = REFERENCE_M * 10 ** ((c["tag_power_dbm"] - reader["tag_chip_sensitivity_dbm"]) / 20.0)
    reverse = REFERENCE_M * 10 ** ((c["rssi_dbm"] - reader["sensitivity_dbm"]) / 40.0)
    return forward, reverse


def nec_feed_current(nec2c, work, height_m, load, ground_eps=None):
    """ground_eps: None for a perfect ground, else (ε', σ S/m) for NEC-2's Sommerfeld ground."""
    if height_m <= 0:
        ground = "GN -1"
    elif ground_eps is None:
        ground = "GN 1"
    else:
        ground = f"GN 2 0 0 0 {ground_eps[0]:.8g} {ground_eps[1]:.8g}"
    z = height_m if height_m > 0 else 1.0
    deck = (f"CM tag_on_metal\nCE\nGW 1 41 0 {-LENGTH_M / 2} {z} 0 {LENGTH_M / 2} {z} {RADIUS_M}\n"
            f"GE {1 if height_m > 0 else 0}\n{ground}\n")
    if load is None:
        deck += "EX 0 1 21 0 1.0 0.0\n"
    else:
        deck += f"LD 4 1 21 21 {load.real} {load.imag}\nEX 1 1 1 0 0.0 90.0 0.0\n"
    deck += f"FR 0 1 0 0 {FREQUENCY_HZ / 1e6} 0\nXQ\nEN\n"
    name = os.path.join(work, f"h{height_m}_{'src' if load is None else 'pw'}")
    with open(name + ".nec", "w") as f:
        f.write(deck)
    subprocess.run([nec2c, "-i", name + ".nec", "-o", name + ".out"], check=True, capture_output=True)
    out = open(name + ".out").read()
    if load is None:
        at = out.index("ANTENNA INPUT PARAMETERS")
        row = out[at:].splitlines()[3].split()
        return complex(float(row[6]), float(row[7]))
    at = out.index("CURRENTS AND LOCATION")
    for line in out[at:].splitlines():
        parts = line.split()
        if len(parts) >= 9 and parts[0] == "21" and parts[1] == "1":
            return float(parts[8])
    raise RuntimeError("no feed current in " + name + ".out")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("out_dir")
    ap.add_argument("--backing", default="metal", help="metal, water, any builtin material, or dielectric:EPS_R:SIGMA_S_M")
    ap.add_argument("--png")
    a = ap.parse_args()
    stem = "tag_on_" + a.backing.replace(":", "_")
    if not os.access(a.binary, os.X_OK):
        fail(f"{a.binary}: not an executable rfidray binary")
    os.makedirs(a.out_dir, exist_ok=True)
    work = tempfile.mkdtemp(prefix="tag_on_metal_")
    try:
        scene = os.path.join(work, "far.obj")  # one tiny triangle far away: free space for every path that matters
        with open(scene, "w") as f:
            f.write("v 1000 1000 1000\nv 1000.01 1000 1000\nv 1000 1000.01 1000\nf 1 2 3\n")
        free = link(a.binary, scene, [])
        free_fwd, free_rev = ranges(free, "raytraced")
        tagged_free = link(a.binary, scene, ["--tag-antenna", f"dipole:{LENGTH_M}:{RADIUS_M}", "--tag-backing", "none"])
        rows = []
        for d in DISTANCES_M:
            point = link(a.binary, scene, ["--tag-antenna", f"dipole:{LENGTH_M}:{RADIUS_M}", "--tag-chip", "matched",
                                           "--tag-backing", f"{a.backing}:{d}"])
            t = point["tag_antenna"]
            image = complex(t["image_factor"]["re"], t["image_factor"]["im"])
            # The point tag with the plate as an image path only: the free link's ranges scaled by |image|.
            pt_fwd, pt_rev = free_fwd * abs(image), free_rev * abs(image)
            fwd, rev = ranges(point, "raytraced")
            rows.append({"distance_m": d, "point_tag_range_m": min(pt_fwd, pt_rev), "model_forward_m": fwd,
                         "model_reverse_m": rev, "model_range_m": min(fwd, rev),
                         "power_transfer_db": t["power_transfer_db"], "chip_power_factor_db": t["chip_power_factor_db"],
                         "image_db": 20 * math.log10(abs(image)), "impedance_re_ohm": t["impedance_re_ohm"],
                         "impedance_im_ohm": t["impedance_im_ohm"], "nec_forward_m": ""})
        nec2c = shutil.which("nec2c")
        nec_note = "nec2c not found: no NEC-2 points"
        impedance_rows = []
        ground_eps = None
        backing = link(a.binary, scene, ["--tag-antenna", f"dipole:{LENGTH_M}:{RADIUS_M}", "--tag-backing",
                                                     f"{a.backing}:0.01"])["tag_antenna"]["backing"]
        if not backing["perfect_conductor"]:
            eps = backing["relative_permittivity"]
            ground_eps = (eps["re"], -eps["im"] * 2 * math.pi * FREQUENCY_HZ * 8.8541878128e-12)
        if nec2c:
            z_free = nec_feed_current(nec2c, work, 0.0, None)
            load = z_free.conjugate()
            i_free = nec_feed_current(nec2c, work, 0.0, load)
            t_free = tagged_free["tag_antenna"]
            fwd_free, _ = ranges(tagged_free, "raytraced")
            for d in NEC_DISTANCES_M:
                z_d = nec_feed_current(nec2c, work, d, None, ground_eps)
                zr = link(a.binary, scene, ["--tag-antenna", f"dipole:{LENGTH_M}:{RADIUS_M}", "--tag-backing", f"{a.backing}:{d}"])["tag_antenna"]
                z_ours = complex(zr["impedance_re_ohm"], zr["impedance_im_ohm"])
                impedance_rows.append((d, z_ours, z_d, abs(z_ours - z_d) / abs(z_d)))
                i_d = nec_feed_current(nec2c, work, d, load, ground_eps)
                rows.append({"distance_m": d, "point_tag_range_m": "", "model_forward_m": "", "model_reverse_m": "",
                             "model_range_m": "", "power_transfer_db": "", "chip_power_factor_db": "", "image_db": "",
                             "impedance_re_ohm": "", "impedance_im_ohm": "",
                             "nec_forward_m": fwd_free * i_d / i_free})
            nec_note = f"NEC-2 free-space impedance {z_free.real:.3f}{z_free.imag:+.3f}j ohm (41 segments)"
            if ground_eps:
                nec_note += f"; NEC-2 Sommerfeld ground eps' {ground_eps[0]:.3f}, sigma {ground_eps[1]:.4g} S/m"
        rows.sort(key=lambda r: (r["distance_m"], r["nec_forward_m"] != ""))
        cols = list(rows[0].keys())
        with open(os.path.join(a.out_dir, stem + ".csv"), "w") as f:
            f.write(",".join(cols) + "\n")
            for r in rows:
                f.write(",".join("" if r[c] == "" else (f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]))
                                 for c in cols) + "\n")
        with open(os.path.join(a.out_dir, stem + ".log"), "w") as f:
            f.write(f"# python3 bench/tag_on_metal.py {a.binary} {a.out_dir} --backing {a.backing}\n")
            f.write(f"# free space: point tag read range {min(free_fwd, free_rev):.3f} m "
                    f"(forward {free_fwd:.3f}, reverse {free_rev:.3f}); {nec_note}\n")
            f.write("| d (m) | point tag + image (m) | tag model (m): forward / reverse | tau (dB) | F (dB) | NEC-2 forward (m) |\n")
            f.write("|---|---|---|---|---|---|\n")
            for r in rows:
                if r["model_range_m"] != "":
                    f.write(f"| {r['distance_m']:g} | {r['point_tag_range_m']:.2f} | {r['model_forward_m']:.2f} / "
                            f"{r['model_reverse_m']:.2f} | {r['power_transfer_db']:.1f} | {r['chip_power_factor_db']:+.1f} | |\n")
                else:
                    f.write(f"| {r['distance_m']:g} | | | | | {r['nec_forward_m']:.2f} |\n")
            if impedance_rows:
                f.write("\n| d (m) | rfidray Z (ohm) | NEC-2 Z (ohm, 41 segments) | abs(dZ)/abs(Z_NEC) |\n|---|---|---|---|\n")
                for d, zo, zn, e in impedance_rows:
                    f.write(f"| {d:g} | {zo.real:.3f} {zo.imag:+.3f}j | {zn.real:.3f} {zn.imag:+.3f}j | {100 * e:.1f} % |\n")
        png = a.png or os.path.join(a.out_dir, stem + ".png")
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            import matplotlib.ticker
        except ImportError:
            print("tag_on_metal.py: matplotlib not installed: no chart", file=sys.stderr)
            return 0
        m = [r for r in rows if r["model_range_m"] != ""]
        n = [r for r in rows if r["nec_forward_m"] != ""]
        fig, ax = plt.subplots(figsize=(8, 4.6))
        x = [r["distance_m"] * 100 for r in m]
        ax.plot(x, [r["point_tag_range_m"] for r in m], "k--", label="point tag, surface as image path only (rfidray without the model)")
        ax.plot(x, [r["model_forward_m"] for r in m], "C0-", label="dipole tag model: forward link (chip powered)")
        ax.plot(x, [r["model_reverse_m"] for r in m], "C1-", label="dipole tag model: reverse link (backscatter)")
        if n:
            ax.plot([r["distance_m"] * 100 for r in n], [r["nec_forward_m"] for r in n], "C0o", label="NEC-2 (nec2c): forward link")
        ax.axhline(min(free_fwd, free_rev), color="0.6", lw=0.8, label=f"free space ({min(free_fwd, free_rev):.1f} m)")
        ax.set_xscale("log")
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        what = "metal plate" if backing["perfect_conductor"] else f"{backing['material']} half-space"
        ax.set_xlabel(f"distance of the tag to the {what} behind it (cm)")
        ax.set_ylabel("read range (m)")
        ax.set_title(f"Half-wave dipole tag (0.166 m, 866 MHz, chip matched in free space) before a {what}", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7.5, loc="upper left")
        fig.tight_layout()
        fig.savefig(png, dpi=110)
        print(f"wrote {os.path.join(a.out_dir, stem + '.csv')}, {stem}.log and {png}")
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
