#!/usr/bin/env python3
"""Shrink a failing scenario file while it still fails.

    python3 testdata/known-failures/minimize.py KSS IN.json OUT.json T [ARGS...]

KSS is a `kss` binary, IN.json the failing scenario, T the time of the
failure (the `until` cut tries 4 T, 100 T and 10^6 T), ARGS the options of
the failing run (default: `--approximate-above 0 --audit`). A candidate is
kept when `kss run -q ARGS` still exits with status 4 (an internal error)
and `kss run -q --structure brute` still reports a collision on it. It
drops flight-plan changes and polygons one at a time until none can go,
then cuts `until`. Vertices are left alone (removing one may break
convexity).
"""
import copy
import json
import subprocess
import sys


def main():
    kss, src, dst, t_fail = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
    args = sys.argv[5:] or ["--approximate-above", "0", "--audit"]
    trial = dst + ".try.json"

    def run(d, extra):
        with open(trial, "w") as f:
            json.dump(d, f)
        try:
            return subprocess.run([kss, "run", "-q", *extra, trial],
                                  capture_output=True, text=True, timeout=120)
        except subprocess.TimeoutExpired:
            return None

    def still_fails(d):
        r = run(d, args)
        if r is None or r.returncode != 4:
            return False
        b = run(d, ["--structure", "brute"])
        return b is not None and b.returncode == 0 and b.stdout.strip() != ""

    d = json.load(open(src))
    assert still_fails(d), "the input does not fail"
    changed = True
    while changed:
        changed = False
        for i in reversed(range(len(d["flight_plan_changes"]))):
            e = copy.deepcopy(d)
            del e["flight_plan_changes"][i]
            if still_fails(e):
                d, changed = e, True
        for i in reversed(range(len(d["polygons"]))):
            e = copy.deepcopy(d)
            gone = e["polygons"].pop(i)["id"]
            e["flight_plan_changes"] = [c for c in e["flight_plan_changes"] if c["id"] != gone]
            if len(e["polygons"]) >= 2 and still_fails(e):
                d, changed = e, True
    for until in (4 * t_fail, 100 * t_fail, 1e6 * t_fail):
        if until < d["until"]:
            e = copy.deepcopy(d)
            e["until"] = until
            e["flight_plan_changes"] = [c for c in e["flight_plan_changes"] if c["time"] < until]
            if still_fails(e):
                d = e
                break
    with open(dst, "w") as f:
        json.dump(d, f, indent=1)
    print(len(d["polygons"]), "polygons,", len(d["flight_plan_changes"]),
          "flight-plan changes, until", d["until"])


if __name__ == "__main__":
    main()
