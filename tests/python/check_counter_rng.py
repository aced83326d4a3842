#!/usr/bin/env python3
"""engine/sensor's random numbers against independent packages:

- the words of its Philox4x64-10 streams against numpy.random.Philox, the same generator written
  by others (numpy adds 1 to counter word 0 before each block, so block {c0, c1, c2, k} is numpy's
  first block from the counter [c0 - 1, c1, c2, k]);
- its Poisson counts (10^6 per mean, one stream per sample) against scipy.stats.poisson's pmf by
  Pearson's chi-squared test, bins merged until each expects at least 5 counts. The samples are
  fixed by their keys, so the test cannot flake: a p-value below 10^-4 means a wrong sampler.

    check_counter_rng.py PREFIX   (reads PREFIX_words.csv and PREFIX_poisson.csv)"""
import csv
import sys
from collections import defaultdict

import numpy as np
from scipy import stats

prefix = sys.argv[1]
failures = []

rows = list(csv.DictReader(open(prefix + "_words.csv")))
streams = defaultdict(list)
for r in rows:
    streams[tuple(int(r[k]) for k in ("k0", "k1", "c0", "c1", "c2"))].append(int(r["word"]))
checked = 0
for (k0, k1, c0, c1, c2), words in streams.items():
    for block in range(len(words) // 4):
        counter = [(c0 - 1) % 2**64, c1 if c0 else (c1 - 1) % 2**64, c2 if (c0 or c1) else (c2 - 1) % 2**64, block + 1]
        want = np.random.Philox(counter=np.array(counter, dtype=np.uint64),
                                key=np.array([k0, k1], dtype=np.uint64)).random_raw(4)
        if [int(v) for v in want] != words[4 * block:4 * block + 4]:
            failures.append(f"stream key ({k0}, {k1}) counter ({c0}, {c1}, {c2}) block {block + 1} differs from numpy")
        checked += 4
print(f"{checked} words of {len(streams)} streams against numpy.random.Philox: "
      f"{'all equal' if not failures else 'DIFFERENT'}")

by_mean = defaultdict(dict)
for r in csv.DictReader(open(prefix + "_poisson.csv")):
    by_mean[float(r["mean"])][int(r["k"])] = int(r["count"])
for mean, hist in sorted(by_mean.items()):
    n = sum(hist.values())
    lo, hi = int(stats.poisson.ppf(1e-9, mean)), int(stats.poisson.isf(1e-9, mean)) + 1
    ks = np.arange(lo, hi + 1)
    expected = stats.poisson.pmf(ks, mean) * n
    expected[0] += stats.poisson.cdf(lo - 1, mean) * n
    expected[-1] += stats.poisson.sf(hi, mean) * n
    observed = np.array([hist.get(int(k), 0) for k in ks], float)
    observed[0] += sum(v for k, v in hist.items() if k < lo)
    observed[-1] += sum(v for k, v in hist.items() if k > hi)
    # Merge bins from both ends inwards until every bin expects at least 5.
    eo, oo, e_acc, o_acc = [], [], 0.0, 0.0
    for e, o in zip(expected, observed):
        e_acc += e
        o_acc += o
        if e_acc >= 5:
            eo.append(e_acc)
            oo.append(o_acc)
            e_acc = o_acc = 0.0
    eo[-1] += e_acc
    oo[-1] += o_acc
    eo, oo = np.array(eo), np.array(oo)
    eo *= oo.sum() / eo.sum()
    chi2, p = stats.chisquare(oo, eo)
    print(f"Poisson mean {mean:g}: {n} counts in {len(eo)} bins, chi2 {chi2:.1f}, p {p:.3f}")
    if p < 1e-4:
        failures.append(f"mean {mean}: chi-squared p = {p:.2e}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
