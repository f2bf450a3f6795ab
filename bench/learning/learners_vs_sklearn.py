#!/usr/bin/python3
"""Our GPR / GMR / joint GMR (the `minigolf` binary) against scikit-learn on the same data.

Synthetic, seeded "sloped field" data: xi = hole - ball in [0.5, 3] x [-1.2, 1.2] m, the hole is
uphill towards +y, so the angle bends uphill with distance and the speed grows with distance and
with the climb; Gaussian noise on both outputs (0.02 rad, 0.03 m/s), like a teacher's examples.
Sets (--sets): "noisy" (that), "clean" (the same law, noise 1e-3 rad and 1e-3 m/s: nearly
noise-free), "1d" and "1d-clean" (xi_y = 0: one input, xi_x, noisy / nearly noise-free).

scikit-learn side (Debian's python3-sklearn; run with /usr/bin/python3):
  GPR: GaussianProcessRegressor(C * RBF(ARD) + WhiteKernel, normalize_y=True,
       n_restarts_optimizer = restarts - 1), one per output, as in the GPML/sklearn docs.
  GMR: GaussianMixture(K, full covariances, defaults) on (xi, output) or (xi, angle, speed), then
       the same Gaussian conditioning (sklearn has no GMR), predictive variance by the law of total
       covariance.
Ours: trained by `bench_learning_fit` (the same mg::learning::train as `minigolf train`, same
defaults) which reports the in-process fit time, like sklearn's `fit()` time; predictions by
`minigolf predict` on the model file it wrote. With --ours-args the model is trained by
`minigolf train ARGS` instead and the time is that of the whole process (start-up included).

Usage: /usr/bin/python3 bench/learning/learners_vs_sklearn.py [--binary build/src/cli/minigolf]
       [--sizes 10,20,30,50] [--seeds 5] [--restarts 10]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
from sklearn.exceptions import ConvergenceWarning
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel
from sklearn.mixture import GaussianMixture

NOISE = (0.02, 0.03)
SETS = {"noisy": (NOISE, 2), "clean": ((1e-3, 1e-3), 2), "1d": (NOISE, 1), "1d-clean": ((1e-3, 1e-3), 1)}


def sloped_field(n, rng, noise=NOISE, dims=2):
    x = rng.uniform(0.5, 3.0, n)
    y = rng.uniform(-1.2, 1.2, n) if dims == 2 else np.zeros(n)
    d = np.hypot(x, y)
    angle = np.arctan2(y, x) + 0.25 * np.tanh(d) * np.cos(np.arctan2(y, x)) + 0.1 * np.sin(2.0 * y)
    speed = np.sqrt(1.2 * d + 0.25) + 0.15 * y + 0.05 * np.sin(3.0 * x)
    angle = angle + rng.normal(0.0, noise[0], n)
    speed = speed + rng.normal(0.0, noise[1], n)
    xi = np.column_stack([x, y]) if dims == 2 else x[:, None]
    return xi, np.column_stack([angle, speed])


def write_csv(path, xi, out):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["xi_x", "xi_y"][: xi.shape[1]] + ["angle", "speed"])
        for a, b in zip(xi, out):
            w.writerow([repr(float(v)) for v in (*a, *b)])


def scores(y, mean, std):
    var = np.maximum(std, 1e-12) ** 2
    mse = np.mean((y - mean) ** 2, axis=0)
    nlpd = np.mean(0.5 * np.log(2 * np.pi * var) + 0.5 * (y - mean) ** 2 / var, axis=0)
    return mse, nlpd


def sk_gpr(xi, out, xv, restarts, seed):
    t0 = time.perf_counter()
    models = []
    for o in range(out.shape[1]):
        kernel = ConstantKernel(1.0, (1e-4, 1e4)) * RBF([1.0] * xi.shape[1], (1e-2, 1e2)) + WhiteKernel(1e-2, (1e-8, 1e1))
        m = GaussianProcessRegressor(kernel, normalize_y=True, n_restarts_optimizer=restarts - 1, random_state=seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            m.fit(xi, out[:, o])
        models.append(m)
    fit = time.perf_counter() - t0
    means, stds = zip(*(m.predict(xv, return_std=True) for m in models))
    return np.column_stack(means), np.column_stack(stds), fit


def condition(gm, x, n_in):
    """GMR on a fitted sklearn GaussianMixture: E and Cov of the last dims given the first n_in."""
    k = gm.n_components
    n = x.shape[0]
    n_out = gm.means_.shape[1] - n_in
    logw = np.zeros((n, k))
    cm = np.zeros((n, k, n_out))
    cc = np.zeros((k, n_out, n_out))
    for j in range(k):
        mu, s = gm.means_[j], gm.covariances_[j]
        sii, soi, soo = s[:n_in, :n_in], s[n_in:, :n_in], s[n_in:, n_in:]
        a = np.linalg.solve(sii, soi.T).T
        diff = x - mu[:n_in]
        maha = np.sum(diff * np.linalg.solve(sii, diff.T).T, axis=1)
        logw[:, j] = np.log(gm.weights_[j]) - 0.5 * (maha + np.linalg.slogdet(2 * np.pi * sii)[1])
        cm[:, j, :] = mu[n_in:] + diff @ a.T
        cc[j] = soo - a @ soi.T
    logw -= logw.max(axis=1, keepdims=True)
    h = np.exp(logw)
    h /= h.sum(axis=1, keepdims=True)
    mean = np.einsum("nk,nko->no", h, cm)
    d = cm - mean[:, None, :]
    var = np.einsum("nk,ko->no", h, np.stack([np.diag(c) for c in cc])) + np.einsum("nk,nko->no", h, d * d)
    return mean, np.sqrt(np.maximum(var, 0.0))


def sk_gmr(xi, out, xv, k, seed, joint):
    t0 = time.perf_counter()
    if joint:
        gms = [GaussianMixture(k, covariance_type="full", random_state=seed).fit(np.column_stack([xi, out]))]
    else:
        gms = [GaussianMixture(k, covariance_type="full", random_state=seed).fit(np.column_stack([xi, out[:, o]]))
               for o in range(out.shape[1])]
    fit = time.perf_counter() - t0
    n_in = xi.shape[1]
    if joint:
        return (*condition(gms[0], xv, n_in), fit)
    parts = [condition(g, xv, n_in) for g in gms]
    return np.column_stack([p[0][:, 0] for p in parts]), np.column_stack([p[1][:, 0] for p in parts]), fit


def ours(binary, fit_binary, method, train_csv, query_csv, model, k, restarts, seed, extra=(), dims=2, cli=False,
         select=""):
    kk = str(k) if method != "gpr" and not select else "0"
    if select and method != "gpr":
        extra = ["--select", select, *extra]
    if extra or cli or dims != 2 or select:  # options only the CLI knows: train with it, time the whole process
        args = [binary, "train", "--method", method, train_csv, "-o", model, "--seed", str(seed), "--restarts",
                str(restarts), "--gaussians", kk, "--inputs", ",".join(["xi_x", "xi_y"][:dims]), *extra]
        t0 = time.perf_counter()
        subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
        fit = time.perf_counter() - t0
    else:
        res = subprocess.run([fit_binary, train_csv, method, kk, str(restarts), str(seed), model], check=True,
                             capture_output=True, text=True)
        fit = json.loads(res.stdout)["fit_seconds"]
    res = subprocess.run([binary, "predict", model, query_csv], check=True, capture_output=True, text=True)
    rows = list(csv.reader(res.stdout.splitlines()))
    hdr = rows[0]
    data = np.array([[float(v) for v in r] for r in rows[1:]])
    mean = data[:, [hdr.index("angle_mean"), hdr.index("speed_mean")]]
    std = data[:, [hdr.index("angle_std"), hdr.index("speed_std")]]
    return mean, std, fit


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.path.join(here, "..", "..", "build", "src", "cli", "minigolf"))
    ap.add_argument("--fit-binary", default=os.path.join(here, "..", "..", "build", "bench", "learning",
                                                         "bench_learning_fit"))
    ap.add_argument("--sizes", default="10,20,30,50")
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--restarts", type=int, default=10)
    ap.add_argument("--validation", type=int, default=300)
    ap.add_argument("--ours-args", default="", help="extra options for `minigolf train`, e.g. '--reg-covar 1e-2'")
    ap.add_argument("--only", default="", help="comma list of methods to run: GPR,GMR,joint GMR")
    ap.add_argument("--sets", default="noisy", help="comma list of data sets: " + ",".join(SETS))
    ap.add_argument("--ours-select", default="", choices=["", "cv", "bic"],
                    help="ours chooses K from the data (`train --gaussians 0 --select ...`); sklearn keeps the table's K")
    ap.add_argument("--cli", action="store_true", help="train ours with `minigolf train` (no bench binary needed)")
    ap.add_argument("--check", type=float, default=None, metavar="TOL",
                    help="exit 1 unless ours' mean MSE is <= (1 + TOL) x scikit-learn's for every "
                         "(set, N, GMM method, output), or the paired difference over seeds is within 2 standard errors")
    a = ap.parse_args()
    sizes = [int(s) for s in a.sizes.split(",")]

    rows = []
    per_seed = {}  # (set, N, method, library) -> (seeds x 2) validation MSEs, for paired comparisons
    with tempfile.TemporaryDirectory() as tmp:
        for set_name in a.sets.split(","):
            noise, dims = SETS[set_name]
            for n in sizes:
                k = 2 if n <= 10 else 3
                acc = {}
                for s in range(a.seeds):
                    rng = np.random.default_rng(1000 * n + s)
                    xi, out = sloped_field(n, rng, noise, dims)
                    xv, ov = sloped_field(a.validation, rng, noise, dims)
                    tr, va, model = (os.path.join(tmp, f) for f in ("train.csv", "val.csv", "model.json"))
                    write_csv(tr, xi, out)
                    write_csv(va, xv, ov)
                    extra = a.ours_args.split()

                    def mine(method):
                        return ours(a.binary, a.fit_binary, method, tr, va, model, k, a.restarts, s + 1, extra,
                                    dims, a.cli, a.ours_select)

                    jobs = {
                        ("GPR", "ours"): lambda: mine("gpr"),
                        ("GPR", "sklearn"): lambda: sk_gpr(xi, out, xv, a.restarts, s),
                        ("GMR", "ours"): lambda: mine("gmr"),
                        ("GMR", "sklearn"): lambda: sk_gmr(xi, out, xv, k, s, joint=False),
                        ("joint GMR", "ours"): lambda: mine("joint-gmr"),
                        ("joint GMR", "sklearn"): lambda: sk_gmr(xi, out, xv, k, s, joint=True),
                    }
                    only = [m for m in a.only.split(",") if m]
                    runs = {key: job() for key, job in jobs.items() if not only or key[0] in only}
                    for key, (mean, std, fit) in runs.items():
                        mse, nlpd = scores(ov, mean, std)
                        acc.setdefault(key, []).append((*mse, *nlpd, fit))
                for (method, lib), vals in acc.items():
                    v = np.mean(np.array(vals), axis=0)
                    rows.append((set_name, n, k, method, lib, *v))
                    per_seed[(set_name, n, method, lib)] = np.array(vals)[:, :2]

    print(f"sloped field, {a.seeds} seeds per size, {a.validation} validation points with the set's noise "
          f"(noisy: angle {NOISE[0]} rad, speed {NOISE[1]} m/s, noise floor MSE {NOISE[0]**2:.1e}, {NOISE[1]**2:.1e}; "
          f"clean: 1e-3 and 1e-3); GPR starts {a.restarts}; fit times wall clock "
          f"({'whole `minigolf train` process' if a.cli or a.ours_args else 'in-process'} for ours)\n")
    print("| set | N | K | method | library | MSE angle [rad^2] | MSE speed [(m/s)^2] | NLPD angle | NLPD speed | fit time [ms] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for set_name, n, k, method, lib, ma, ms, na, ns, fit in rows:
        kk = "-" if method == "GPR" else str(k)
        print(f"| {set_name} | {n} | {kk} | {method} | {lib} | {ma:.3e} | {ms:.3e} | {na:.3f} | {ns:.3f} | {fit*1e3:.1f} |")

    if a.check is None:
        return 0
    # Paired over seeds (same training and validation sets): ours is worse only if its mean MSE is
    # above (1 + TOL) x scikit-learn's AND the paired difference is more than 2 standard errors,
    # i.e. a difference the seeds measured, not the luck of which EM optimum a few seeds reached.
    failures = []
    print("\n| set | N | method | output | ours / sklearn MSE | paired difference (ours - sklearn) +- 2 SE | verdict |")
    print("|---|---|---|---|---|---|---|")
    for (set_name, n, method, lib), mine in per_seed.items():
        if lib != "ours" or method == "GPR" or (set_name, n, method, "sklearn") not in per_seed:
            continue
        ref = per_seed[(set_name, n, method, "sklearn")]
        for o, name in enumerate(("angle", "speed")):
            d = mine[:, o] - ref[:, o]
            se = d.std(ddof=1) / math.sqrt(len(d)) if len(d) > 1 else math.inf
            worse = d.mean() > a.check * ref[:, o].mean() and d.mean() > 2.0 * se
            better = d.mean() < -2.0 * se
            verdict = "worse" if worse else ("better" if better else "no measured difference")
            print(f"| {set_name} | {n} | {method} | {name} | {mine[:, o].mean() / ref[:, o].mean():.2f} | "
                  f"{d.mean():+.2e} +- {2 * se:.1e} | {verdict} |")
            if worse:
                failures.append(f"{set_name} N={n} {method} {name}: ours {mine[:, o].mean():.3e} > (1+{a.check}) x "
                                f"sklearn {ref[:, o].mean():.3e}, paired difference {d.mean():.2e} > 2 SE {2 * se:.1e}")
    for f in failures:
        print("FAILED:", f)
    print(f"check: {len(failures)} of the GMR / joint GMR MSEs measurably worse (> 2 SE, paired over seeds) than "
          f"scikit-learn's by more than {a.check:.0%}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
