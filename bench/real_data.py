#!/usr/bin/env python3
"""rfidray on real reads: the public AdaRF set (real Impinj reads, one antenna at 50 stops along a 1 m stage,
8 hopping carriers 920.625-924.125 MHz in the test splits, one in the training splits) against rfidray's own
simulation of the same setup.

The dataset carries no licence, so it is never part of this repository: fetch it yourself (the public
repository dapowan/AdaRF on GitHub) and give its folder:

    python3 bench/real_data.py --adarf PATH/TO/AdaRF [--rfidray build/rfidray] [-o bench/results/real]

What it does, with rfidray's own commands only:
 1. every run folder (dataset/<d>/<split>/<run>/<stop>.csv) -> `rfidray import --layout per-stop` (antenna at
    the stop positions, facing +y) and a truth CSV built from dataset/config.txt and the tag order in
    codes/config.py, as the dataset's README describes (tags on a row at y = Y, x = X + S·(i - (n-1)/2), cm);
 2. `rfidray calibrate` over the D1 training runs (the only place tuning data comes from) -> antenna.yaml, with
    the D2-D4 training runs as --allowance-pair (they measure the radius allowance, not the antenna);
 3. for each test run of D1-D4, exactly the acceptance command:
    `rfidray localize R.csv --truth T.csv --method all --height-known --mirror-prior boresight --max-range 3
     --antenna-file antenna.yaml --tag-spacing-m S --json` (S: the row's spacing as laid out, config.txt);
 4. the same stage, tags and carriers simulated by rfidray (ideal channel; single-bounce over a floor with the
    calibrated antenna's hardware effects; and the same with each tag's phase ripple, TAG_RIPPLE below),
    localized the same way;
 5. real_vs_sim.csv, real_vs_sim.md (the README table), real_vs_sim.png, antenna.yaml; the per-run JSON stays
    in the work folder (--keep), since it names the set's tags.

--quick takes the first runs of each split only (for a smoke test). --peers adds the set's own Tagoram,
MobiTagbot, RF-Scanner and STPP (bench/real_peers.py, imported from --adarf at run time) on the same runs and
truth: real_vs_peers.md.
"""
import argparse
import csv
import json
import math
import os
import random
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import zlib

CARRIERS_HZ = [920.625e6 + 0.5e6 * k for k in range(8)]  # AdaRF README: 920.625 to 924.125 MHz, 0.5 MHz steps
METHODS = ["hyperbolic", "nlls", "sar"]
# Each tag's phase ripple (core/phase_pattern.h): median RMS, wiggle scale, log-sd of the RMS between tags. Chosen
# on 42 held-out D1 training runs (210 tags; every 5th run from run 40, none used by the calibration), to match
# the real reads' residual (median / p90) and ok fraction there: real NLLS 37/210 ok, residual 0.295 / 0.624
# rad; simulated 34/210, 0.281 / 0.615 rad. The test splits were not used to choose it.
TAG_RIPPLE = "{ripple_rms_rad: 0.35, ripple_scale_deg: 30, ripple_spread: 0.6}"


def fail(message):
    print("real_data: error: " + message, file=sys.stderr)
    sys.exit(2)


def run(cmd, capture=True):
    """Runs an rfidray command; exits with its message when it fails. One OpenMP thread, so a result's time_ms
    is the CPU time of that tag (comparable with the peers' process time)."""
    r = subprocess.run(cmd, capture_output=capture, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    if r.returncode != 0:
        fail("command failed (exit %d): %s\n%s" % (r.returncode, " ".join(cmd), (r.stderr or "")[-2000:]))
    return r.stdout


def read_tag_orders(config_py):
    """EPC_<C|T><d> lists of codes/config.py: the tags of each dataset in their order along the row."""
    if not os.path.isfile(config_py):
        fail(config_py + ": not found (give the AdaRF repository folder with --adarf)")
    text = open(config_py, encoding="utf-8").read()
    lists = {}
    for name, body in re.findall(r"^(EPC_[CT]\d)\s*=\s*\[(.*?)\]", text, re.S | re.M):
        lists[name] = re.findall(r"b'(\d+)'", body)
    for name, alias in re.findall(r"^(EPC_[CT]\d)\s*=\s*(EPC_[CT]\d)\s*$", text, re.M):
        lists[name] = lists[alias]
    separations = {}
    for d, split, sep in re.findall(r"CONFIG_D(\d)_(TRAIN|TEST)\s*=\s*\{[^}]*?'separation':\s*([\d.]+)", text):
        separations[(int(d), split.lower())] = float(sep)
    return lists, separations


def read_run_config(config_txt):
    """dataset/config.txt: 'A I:X Y P F [S]' -> {(MMDD, index): (X cm, Y cm, S cm or None)}."""
    if not os.path.isfile(config_txt):
        fail(config_txt + ": not found")
    out = {}
    with open(config_txt, encoding="utf-8-sig") as f:
        for line_no, line in enumerate(f, 1):
            items = line.split()
            if line_no == 1 or not items:
                continue
            m = re.match(r"(\d+)-(\d+):([\d.]+)$", items[1]) if len(items) >= 5 else None
            if not m:
                fail("%s:%d: expected 'A I:X Y P F [S]'" % (config_txt, line_no))
            sep = float(items[5]) if len(items) > 5 else None
            for i in range(int(m.group(1)), int(m.group(2)) + 1):
                out[(items[0], i)] = (float(m.group(3)), float(items[2]), sep)
    return out


def truth_of_run(run_name, d, split, run_config, tag_orders, separations):
    """[(epc, x_m, y_m, z_m)] for a run folder 'YYMMDD-II-P-F' (README: tags on one row, adjacent S cm apart)."""
    m = re.match(r"(\d\d)(\d{4})-(\d+)-(\d+)-(\d+)$", run_name)
    if not m:
        return None
    key = (m.group(2), int(m.group(3)))
    if key not in run_config:
        return None
    x_cm, y_cm, sep_cm = run_config[key]
    tags = tag_orders.get("EPC_%s%d" % ("C" if split == "train" else "T", d))
    if not tags:
        return None
    if sep_cm is None:
        sep_cm = separations.get((d, split))
    if not sep_cm:
        return None
    mid = (len(tags) - 1) / 2.0
    return [(epc, (x_cm + sep_cm * (i - mid)) / 100.0, y_cm / 100.0, 0.0) for i, epc in enumerate(tags)]


def filter_to_truth(readings, truth_names, out):
    """Keeps the reads of tags with ground truth (runs also saw tags that are not on the row)."""
    kept = 0
    with open(readings, encoding="utf-8") as src, open(out, "w", encoding="utf-8") as dst:
        header = src.readline()
        dst.write(header)
        name_col = header.strip().split(",").index("name")
        for line in src:
            if line.split(",")[name_col] in truth_names:
                dst.write(line)
                kept += 1
    return kept


def convert(args, d, split, run_dir, truth, work):
    name = os.path.basename(run_dir)
    base = os.path.join(work, "D%d" % d, split, name)
    os.makedirs(base, exist_ok=True)
    readings = os.path.join(base, "readings.csv")
    truth_csv = os.path.join(base, "truth.csv")
    if args.keep and os.path.isfile(readings) and os.path.isfile(truth_csv):
        return readings, truth_csv  # converted by an earlier run into the same --keep folder
    raw = os.path.join(base, "imported.csv")
    # The README of the set calls its y column ("1.63") invalid, default 0: a constant replaces it.
    run([args.rfidray, "import", "--layout", "per-stop", run_dir, "--columns", "y=0", "--antenna-rpy", "0,0,90",
         "--antenna-name", "stage", "-q", "-o", raw])
    if filter_to_truth(raw, {t[0] for t in truth}, readings) == 0:
        return None
    os.remove(raw)
    with open(truth_csv, "w") as f:
        f.write("name,x,y,z\n")
        for epc, x, y, z in truth:
            f.write("%s,%.4f,%.4f,%.4f\n" % (epc, x, y, z))
    return readings, truth_csv


def layout_spacing_m(truth_csv):
    """The run's tag spacing as laid out (the row's S in config.txt): the median over its tags of the distance to
    the nearest other tag; None for a single tag."""
    with open(truth_csv) as f:
        tags = [(float(r["x"]), float(r["y"]), float(r["z"])) for r in csv.DictReader(f)]
    nearest = [min(math.dist(a, b) for j, b in enumerate(tags) if j != i) for i, a in enumerate(tags)] if len(tags) > 1 else []
    return statistics.median(nearest) if nearest else None


def localize(args, readings, truth_csv, antenna_file):
    cmd = [args.rfidray, "localize", readings, "--truth", truth_csv, "--method", "all", "--height-known",
           "--mirror-prior", "boresight", "--max-range", str(args.max_range), "--json"]
    if antenna_file:
        cmd += ["--antenna-file", antenna_file]
        spacing = layout_spacing_m(truth_csv)
        if spacing:  # the radius allowance the antenna file measured on reference tags that far apart
            cmd += ["--tag-spacing-m", "%.4f" % spacing]
    return json.loads(run(cmd))


def error_stats(errs):
    errs = sorted(errs)
    nan = float("nan")
    return {
        "mean_mm": 1e3 * statistics.fmean(errs) if errs else nan,
        "median_mm": 1e3 * statistics.median(errs) if errs else nan,
        "p90_mm": 1e3 * errs[min(len(errs) - 1, int(math.ceil(0.9 * len(errs))) - 1)] if errs else nan,
        "max_mm": 1e3 * errs[-1] if errs else nan,
    }


def stats(results):
    """Per method: ok count, error mean/median/p90/max of ok results, ok outside their uncertainty; and over every
    result with a position (ok + uncertain): count, errors, share inside the 95 % radius, median radius, time."""
    out = {}
    for m in METHODS:
        rows = [r for r in results if r["method"] == m]
        ok = [r for r in rows if r["status"] == "ok" and r.get("error_m") is not None]
        pos = [r for r in rows if r["status"] in ("ok", "uncertain") and r.get("error_m") is not None]
        outside = sum(1 for r in ok if r.get("uncertainty_m") is not None and r["error_m"] > r["uncertainty_m"])
        resid = [r["residual_rad"] for r in rows if r.get("residual_rad")]
        s = {"tags": len(rows), "ok": len(ok), "ok_outside_uncertainty": outside,
             "residual_rms_rad": statistics.fmean(resid) if resid else float("nan")}
        s.update(error_stats([r["error_m"] for r in ok]))
        s["positioned"] = len(pos)
        s.update({"pos_" + k: v for k, v in error_stats([r["error_m"] for r in pos]).items()})
        s["covered"] = sum(1 for r in pos if r["error_m"] <= r["uncertainty_m"])
        s["median_radius_mm"] = 1e3 * statistics.median([r["uncertainty_m"] for r in pos]) if pos else float("nan")
        s["time_ms"] = statistics.fmean([r["time_ms"] for r in rows]) if rows else float("nan")
        out[m] = s
    return out


def simulated_scenario(path, truth, antenna_file, channel, ripple=None, seed=1, extra_meshes=()):
    """The AdaRF stage in rfidray's terms: 50 stops 2 cm apart over x in [0.02, 0.98] m at z = 0 facing +y,
    8 carriers hopping, tags where the run's truth puts them, a concrete floor 0.75 m below (a table top);
    `ripple`: each tag's phase_pattern (drawn from `seed` and the tag's index, so give every run its own seed);
    `extra_meshes`: more scene meshes as YAML flow maps (bench/row_errors_by_distance.py's wall)."""
    stops = [[0.02 + k * 0.96 / 49, 0.0, 0.0] for k in range(50)]
    lines = ["name: stage_1m", "seed: %d" % seed, "channel: %s" % channel, "model: physical"]
    if channel != "ideal":
        here = os.path.dirname(os.path.abspath(path))
        meshes = ["{file: %s, material: concrete, position: [0.5, 0.5, -0.75]}" % os.path.join(here, "floor.obj")]
        lines += ["scene:", "  meshes: [%s]" % ", ".join(meshes + list(extra_meshes))]
    lines += ["antennas:", "  - name: stage", "    frequencies_hz: [%s]" % ", ".join("%.0f" % f for f in CARRIERS_HZ),
              "    hop_dwell_s: 0.125", "    update_rate: 400", "    tx_power_dbm: 30",
              "    noisephi: 0.1", "    phase_bits: 12", "    rssi_resolution_db: 0.5",
              "    pattern: {kind: patch, gain_dbi: 8, beamwidth_deg: 70}",
              "    polarization: rhcp", "    yaw_deg: 90",
              "    waypoints: %s" % json.dumps(stops), "    speed_m_s: 0.02"]
    if antenna_file:
        lines += ["    antenna_file: %s" % os.path.abspath(antenna_file)]
    lines += ["tags:"]
    for epc, x, y, z in truth:
        lines += ["  - {name: '%s', position: [%.4f, %.4f, %.4f], yaw_deg: -90, gain_dbi: 2.15%s}"
                  % (epc, x, y, z, ", phase_pattern: " + ripple if ripple else "")]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_floor(path):
    with open(path, "w") as f:  # 4 m x 4 m, centred where the scenario places it
        f.write("v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\nf 1 2 3\nf 1 3 4\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--adarf", required=True, help="folder of the AdaRF repository (dataset/ and codes/ inside)")
    ap.add_argument("--rfidray", default=os.path.join("build", "rfidray"))
    ap.add_argument("-o", "--output", default=os.path.join("bench", "results", "real"))
    ap.add_argument("--datasets", default="1,2,3,4")
    ap.add_argument("--train-runs", type=int, default=0, help="D1 training runs used by calibrate (0: all)")
    ap.add_argument("--train-every", type=int, default=1,
                    help="calibrate on every K-th D1 training run (the runs are ordered by distance: spreading "
                         "them covers every distance, which separates the phase centre from the pattern)")
    ap.add_argument("--allowance-datasets", default="2,3,4",
                    help="training splits whose runs (every --train-every-th) calibrate only the radius allowance "
                         "(calibrate --allowance-pair): the denser rows the antenna file is used on; '' for none")
    ap.add_argument("--quick", action="store_true", help="two runs per split (smoke test)")
    ap.add_argument("--split", default="test", choices=["test", "train"],
                    help="the runs localized (train: for tuning, with --every/--offset keeping them apart from the "
                         "calibration's)")
    ap.add_argument("--every", type=int, default=1, help="localize every K-th run of the split")
    ap.add_argument("--offset", type=int, default=0, help="... starting from this one")
    ap.add_argument("--peers", action="store_true",
                    help="also run the set's own Tagoram, MobiTagbot, RF-Scanner and STPP (codes/, imported from "
                         "--adarf at run time) on the same runs; real_vs_peers.md")
    ap.add_argument("--peer-results",
                    help="take the peers' per-tag results from an earlier --peers run's --keep folder (D<d>_peers.json, "
                         "same split and runs) instead of running them again (~15 min): their code and the data are "
                         "the same, so are their results")
    ap.add_argument("--peer-every", type=int, default=1,
                    help="run Tagoram and MobiTagbot (0.5-2 s of CPU per tag) on every K-th run only")
    ap.add_argument("--jobs", type=int, default=2, help="processes for the peers")
    ap.add_argument("--no-sim", action="store_true", help="skip the simulated counterpart")
    ap.add_argument("--max-range", type=float, default=3.0,
                    help="localize's search region, m from the path (3: the acceptance command; 1: the depth of "
                         "the peers' hologram grid, the same prior knowledge as theirs)")
    ap.add_argument("--calibration", help="use this antenna file (an earlier run's antenna.yaml, same training "
                                          "options) instead of calibrating again (~12 min)")
    ap.add_argument("--keep", help="keep the converted files in this folder (never inside the repository); runs "
                                   "already converted there are reused")
    args = ap.parse_args()
    if not os.path.isfile(args.rfidray):
        fail(args.rfidray + ": no rfidray binary (build first, or give --rfidray)")
    dataset = os.path.join(args.adarf, "dataset")
    if not os.path.isdir(dataset):
        fail("%s: no dataset/ folder. The AdaRF set is public but unlicensed, so rfidray does not ship it: fetch "
             "the GitHub repository dapowan/AdaRF and pass its folder with --adarf" % args.adarf)
    tag_orders, separations = read_tag_orders(os.path.join(args.adarf, "codes", "config.py"))
    run_config = read_run_config(os.path.join(dataset, "config.txt"))
    os.makedirs(args.output, exist_ok=True)
    work = args.keep or tempfile.mkdtemp(prefix="rfidray-real-")
    datasets = [int(x) for x in args.datasets.split(",")]

    def runs(d, split, every=1, limit=0, offset=0):
        folder = os.path.join(dataset, str(d), split)
        names = sorted(os.listdir(folder)) if os.path.isdir(folder) else []
        if args.quick:
            names = names[:2]
        names = names[offset::max(1, every)]
        if limit > 0:
            names = names[:limit]
        out = []
        for n in names:
            truth = truth_of_run(n, d, split, run_config, tag_orders, separations)
            if truth is None:
                print("real_data: note: %s/%s: no config line or tag list, skipped" % (split, n), file=sys.stderr)
                continue
            conv = convert(args, d, split, os.path.join(folder, n), truth, work)
            if conv:
                out.append((n, conv[0], conv[1], truth, os.path.join(folder, n)))
        return out

    # 2. Calibration on D1 training runs only.
    train = runs(1, "train", args.train_every, args.train_runs)
    if not train:
        fail("no D1 training run could be converted")
    antenna_file = os.path.join(args.output, "antenna.yaml")
    if args.calibration:  # an antenna file calibrate wrote before with the same training runs
        shutil.copyfile(args.calibration, antenna_file)
    else:
        cal_cmd = [args.rfidray, "calibrate", "--height-known", "-o", antenna_file]
        for _, readings, truth_csv, _, _ in train:
            cal_cmd += ["--pair", readings + "," + truth_csv]
        for d in [int(x) for x in args.allowance_datasets.split(",") if x]:
            for _, readings, truth_csv, _, _ in runs(d, "train", args.train_every):
                cal_cmd += ["--allowance-pair", readings + "," + truth_csv]
        print(run(cal_cmd).strip())

    # 3.-4. Test splits: real, and simulated with the same geometry.
    table = []
    write_floor(os.path.join(work, "floor.obj"))
    peer_table = []
    paired_table = []
    with_peers = args.peers or bool(args.peer_results)
    if with_peers:
        sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
        import real_peers
    if args.peers:
        # Imported once here only to fail before any run when codes/ is missing or broken; each worker imports its own.
        real_peers.PeerCode(args.adarf)
    for d in datasets:
        tests = runs(d, args.split, args.every, 0, args.offset)
        real, uncal, sim_ideal, sim_traced, sim_ripple = [], [], [], [], []
        if args.peers:
            peer_rows = run_peers(args, real_peers, d, tests, tag_orders)
            json.dump(peer_rows, open(os.path.join(work, "D%d_peers.json" % d), "w"), indent=1)
        elif args.peer_results:
            stored = os.path.join(args.peer_results, "D%d_peers.json" % d)
            if not os.path.isfile(stored):
                fail("--peer-results: %s: no such file (run once with --peers --keep %s)" % (stored, args.peer_results))
            peer_rows = json.load(open(stored))
        for name, readings, truth_csv, truth, _ in tests:
            j = localize(args, readings, truth_csv, antenna_file)
            # Per-run results name the set's tags: they stay with the converted data, outside the repository.
            json.dump(j, open(os.path.join(work, "D%d_%s.json" % (d, name)), "w"), indent=1)
            # A tag's EPC repeats in every run of a split: (run, name) is what pairs a result with a peer's.
            real += [dict(r, run=name) for r in j["results"]]
            uncal += [dict(r, run=name) for r in localize(args, readings, truth_csv, None)["results"]]
            if args.no_sim or d != 1:
                continue
            for label, channel, bucket, hw, ripple in (("ideal", "ideal", sim_ideal, None, None),
                                                       ("traced", "single-bounce", sim_traced, antenna_file, None),
                                                       ("ripple", "single-bounce", sim_ripple, antenna_file, TAG_RIPPLE)):
                folder = os.path.join(work, "sim", label, name)
                os.makedirs(folder, exist_ok=True)
                scenario = os.path.join(work, "sim_%s_%s.yaml" % (label, name))
                simulated_scenario(scenario, truth, hw, channel, ripple, seed=1 + zlib.crc32(name.encode()) % 100000)
                run([args.rfidray, "simulate", scenario, "-o", folder, "-q"])
                bucket += localize(args, os.path.join(folder, "stage.csv"), truth_csv, hw)["results"]
        rows = [("real, calibrated", real), ("real, uncalibrated", uncal)]
        if d == 1 and not args.no_sim:
            rows += [("simulated, ideal", sim_ideal), ("simulated, single-bounce + hardware", sim_traced),
                     ("simulated, single-bounce + hardware + tag ripple", sim_ripple)]
        for label, results in rows:
            for m, s in stats(results).items():
                table.append(dict(dataset="D%d" % d, data=label, method=m, **s))
        if with_peers:
            for label, results in rows[:2]:
                for m, s in stats(results).items():
                    peer_table.append(dict(dataset="D%d" % d, method=rfidray_method(m, label),
                                           tags=s["tags"], positioned=s["positioned"], ok=s["ok"],
                                           mean_mm=s["pos_mean_mm"], median_mm=s["pos_median_mm"],
                                           p90_mm=s["pos_p90_mm"], max_mm=s["pos_max_mm"], covered=s["covered"],
                                           median_radius_mm=s["median_radius_mm"], cpu_ms=s["time_ms"]))
            for m, s in real_peers.peer_stats(peer_rows).items():
                peer_table.append(dict(dataset="D%d" % d, method=m, ok=None, covered=None,
                                       median_radius_mm=float("nan"), **s))
            paired_table += paired_rows("D%d" % d, rows[:2], peer_rows)

    if with_peers:
        write_peer_table(args.output, peer_table, args)
        write_paired_table(args.output, paired_table, args)
    fields = ["dataset", "data", "method", "tags", "ok", "mean_mm", "median_mm", "p90_mm", "max_mm",
              "ok_outside_uncertainty", "residual_rms_rad", "positioned", "pos_mean_mm", "pos_median_mm",
              "covered", "median_radius_mm"]
    with open(os.path.join(args.output, "real_vs_sim.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fields)
        for r in table:
            w.writerow([("%.4f" % r[k]) if isinstance(r[k], float) else r[k] for k in fields])
    with open(os.path.join(args.output, "real_vs_sim.md"), "w") as f:
        f.write("| dataset | data | method | ok / tags | mean mm | median mm | p90 mm | max mm | ok outside uncertainty "
                "| residual RMS rad | with a position | their mean / median mm | in their 95 % radius | median radius mm |"
                "\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
        for r in table:
            f.write("| %s | %s | %s | %d / %d | %.1f | %.1f | %.1f | %.1f | %d | %.3f | %d | %.1f / %.1f | %s | %.1f |\n" % (
                r["dataset"], r["data"], r["method"], r["ok"], r["tags"], r["mean_mm"], r["median_mm"], r["p90_mm"],
                r["max_mm"], r["ok_outside_uncertainty"], r["residual_rms_rad"], r["positioned"], r["pos_mean_mm"],
                r["pos_median_mm"], percent(r["covered"], r["positioned"]), r["median_radius_mm"]))
    plot(args.output, table)
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    print(open(os.path.join(args.output, "real_vs_sim.md")).read())


def percent(k, n):
    return "%d (%.0f %%)" % (k, 100.0 * k / n) if n else "-"


def run_peers(args, real_peers, d, tests, tag_orders):
    """The set's own methods on the runs of `tests` (in --jobs processes), against the same truth."""
    import multiprocessing
    epcs = [e.encode() for e in tag_orders["EPC_%s%d" % ("T" if args.split == "test" else "C", d)]]
    jobs = []
    for k, (name, _, _, truth, run_dir) in enumerate(tests):
        methods = list(real_peers.PEERS) if k % max(1, args.peer_every) == 0 else ["RF-Scanner", "STPP (x only)"]
        jobs.append((args.adarf, run_dir, epcs, {t[0]: (t[1], t[2]) for t in truth}, methods, args.split))
    with multiprocessing.Pool(max(1, args.jobs)) as pool:
        parts = pool.starmap(peer_job, jobs)
    return [dict(r, run=test[0]) for test, part in zip(tests, parts) for r in part]


_PEER_CODE = {}


def peer_job(adarf, run_dir, epcs, truth, methods, split):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import real_peers
    if adarf not in _PEER_CODE:
        _PEER_CODE[adarf] = real_peers.PeerCode(adarf)
    return real_peers.run_peers_on_run(_PEER_CODE[adarf], run_dir, epcs, truth, methods, split)


def write_peer_table(out_dir, rows, args):
    """real_vs_peers.md / .csv: rfidray's methods (every result with a position) beside the published ones."""
    fields = ["dataset", "method", "tags", "positioned", "ok", "mean_mm", "median_mm", "p90_mm", "max_mm", "covered",
              "median_radius_mm", "cpu_ms"]
    with open(os.path.join(out_dir, "real_vs_peers.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fields)
        for r in rows:
            w.writerow([("%.4f" % r[k]) if isinstance(r[k], float) else ("" if r[k] is None else r[k]) for k in fields])
    with open(os.path.join(out_dir, "real_vs_peers.md"), "w") as f:
        f.write("| split | method | with a position / tags | ok | mean / median / p90 / max mm | in its 95 % radius "
                "| median radius mm | CPU ms per tag |\n|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write("| %s %s | %s | %d / %d | %s | %.0f / %.0f / %.0f / %.0f | %s | %s | %.1f |\n" % (
                r["dataset"], args.split, r["method"], r["positioned"], r["tags"], "-" if r["ok"] is None else r["ok"],
                r["mean_mm"], r["median_mm"], r["p90_mm"], r["max_mm"],
                "-" if r["covered"] is None else percent(r["covered"], r["positioned"]),
                "-" if r["median_radius_mm"] != r["median_radius_mm"] else "%.0f" % r["median_radius_mm"], r["cpu_ms"]))


def rfidray_method(method, data_label):
    """'rfidray nlls, calibrated' for method nlls and rows labelled 'real, calibrated'."""
    return "rfidray %s, %s" % (method, data_label.split(", ")[1])


def paired_rows(dataset, rfidray_rows, peer_rows):
    """Each rfidray method (calibrated and not) against each peer on the tags both place: the means of
    real_vs_peers.md are over different tags (rfidray's over those it answers; Tagoram's and MobiTagbot's over the
    runs they were run on, --peer-every)."""
    if any("run" not in r for r in peer_rows):
        print("real_data: note: %s: the stored peer results have no run names (made before they were kept); "
              "no paired table: run once with --peers" % dataset, file=sys.stderr)
        return []
    out = []
    for peer in dict.fromkeys(r["method"] for r in peer_rows):  # in the order they were run
        theirs = {(r["run"], r["name"]): r["error_m"] for r in peer_rows
                  if r["method"] == peer and r["error_m"] is not None}
        if not theirs:
            continue
        for label, results in rfidray_rows:
            for m in METHODS:
                mine = {(r["run"], r["name"]): r["error_m"] for r in results
                        if r["method"] == m and r["status"] in ("ok", "uncertain") and r.get("error_m") is not None}
                both = sorted(set(mine) & set(theirs))
                if not both:
                    continue
                a = [1e3 * mine[k] for k in both]
                b = [1e3 * theirs[k] for k in both]
                lo, hi = paired_difference_interval({k: 1e3 * (mine[k] - theirs[k]) for k in both})
                out.append(dict(dataset=dataset, method=rfidray_method(m, label), peer=peer,
                                tags=len(both), peer_tags=len(theirs), mean_mm=statistics.fmean(a),
                                peer_mean_mm=statistics.fmean(b), median_mm=statistics.median(a),
                                peer_median_mm=statistics.median(b),
                                closer=sum(1 for x, y in zip(a, b) if x < y),
                                difference_mm=statistics.fmean(a) - statistics.fmean(b),
                                difference_low_mm=lo, difference_high_mm=hi))
    return out


def paired_difference_interval(difference_mm, resamples=2000, seed=1):
    """95 % interval of the mean of rfidray's error minus the peer's over the tags both place, by resampling whole
    runs with replacement (the tags of one run share its row and its day: their differences are not independent,
    and resampling tags alone would make the interval too narrow). difference_mm: {(run, tag): mm}. Seeded:
    the same interval every time. One run only: (nan, nan)."""
    by_run = {}
    for (run_name, _), d in sorted(difference_mm.items()):
        by_run.setdefault(run_name, []).append(d)
    runs = [by_run[r] for r in sorted(by_run)]
    if len(runs) < 2:
        return float("nan"), float("nan")
    rng = random.Random(seed)
    means = []
    for _ in range(resamples):
        pick = [runs[rng.randrange(len(runs))] for _ in runs]
        means.append(statistics.fmean(d for run in pick for d in run))
    means.sort()
    return means[int(0.025 * (resamples - 1))], means[int(round(0.975 * (resamples - 1)))]


def write_paired_table(out_dir, rows, args):
    """real_vs_peers_paired.md / .csv: rfidray and each peer on the same tags."""
    fields = ["dataset", "method", "peer", "tags", "peer_tags", "mean_mm", "peer_mean_mm", "median_mm",
              "peer_median_mm", "closer", "difference_mm", "difference_low_mm", "difference_high_mm"]
    with open(os.path.join(out_dir, "real_vs_peers_paired.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fields)
        for r in rows:
            w.writerow([("%.4f" % r[k]) if isinstance(r[k], float) else r[k] for k in fields])
    with open(os.path.join(out_dir, "real_vs_peers_paired.md"), "w") as f:
        f.write("| split | rfidray method | peer | tags both place / the peer places | mean mm, rfidray / peer "
                "| median mm, rfidray / peer | rfidray closer on | mean difference mm (95 % interval, runs "
                "resampled) |\n|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            f.write("| %s %s | %s | %s | %d / %d | %.0f / %.0f | %.0f / %.0f | %d | %+.0f (%+.0f … %+.0f) |\n" % (
                r["dataset"], args.split, r["method"], r["peer"], r["tags"], r["peer_tags"], r["mean_mm"],
                r["peer_mean_mm"], r["median_mm"], r["peer_median_mm"], r["closer"], r["difference_mm"],
                r["difference_low_mm"], r["difference_high_mm"]))


def plot(out_dir, table):
    """Mean and p90 error per method, real vs simulated (D1), with gnuplot (Debian gnuplot-nox)."""
    if not shutil.which("gnuplot"):
        print("real_data: note: gnuplot not found, no PNG", file=sys.stderr)
        return
    d1 = [r for r in table if r["dataset"] == "D1"]
    labels = sorted({r["data"] for r in d1}, key=lambda s: [r["data"] for r in d1].index(s))
    dat = os.path.join(out_dir, "real_vs_sim.dat")
    with open(dat, "w") as f:
        f.write("method " + " ".join('"%s"' % l for l in labels) + "\n")
        for m in METHODS:
            vals = []
            for l in labels:
                v = [r["mean_mm"] for r in d1 if r["data"] == l and r["method"] == m]
                vals.append("%.2f" % v[0] if v and v[0] == v[0] else "0")
            f.write("%s %s\n" % (m, " ".join(vals)))
    gp = os.path.join(out_dir, "real_vs_sim.gp")
    with open(gp, "w") as f:
        f.write('set terminal pngcairo size 1000,500\nset output "%s"\n' % os.path.join(out_dir, "real_vs_sim.png"))
        f.write('set title "AdaRF D1 test: mean localization error of ok results, real vs simulated"\n')
        f.write('set ylabel "mean error (mm)"\nset style data histograms\nset style fill solid 0.8\nset key outside below horizontal\n')
        f.write('set logscale y\nset grid ytics\n')
        f.write("plot " + ", ".join('"%s" using %d:xtic(1) title columnheader(%d)' % (dat, i + 2, i + 2)
                                     for i in range(len(labels))) + "\n")
    subprocess.run(["gnuplot", gp], check=False)


if __name__ == "__main__":
    main()
