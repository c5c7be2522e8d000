#!/usr/bin/python3
"""mrr's sampling, reproduced outside mrr (docs/validate-your-own.md, docs/spec.md 6 and 7.1).

A renderer that wants the oracle's exact numbers (so that `mrr compare` can judge its SSAO or
SSGI pixel for pixel, without --noise-aware) computes the same kernel and per-pixel rotations.
This file does so in Python with numpy float32 arithmetic, and checks itself against the data
`mrr shaders export DIR` writes into DIR/sampling/sampling.json:

  /usr/bin/python3 examples/mrr_sampling.py DIR/sampling/sampling.json

prints how many kernel points and hash test vectors match, exits 1 on any mismatch. Port the
four functions below (pcg_hash, rotation_hash, hash_to_unit, ssao_kernel) to your language.
"""
import json
import sys

import numpy as np

MASK = 0xFFFFFFFF
SSAO_KERNEL_SEED = 0x5EED5A0
SSGI_KERNEL_SEED = 0x51A61
F = np.float32


def pcg_hash(v):
    """PCG hash of Jarzynski & Olano (JCGT 2020) in 32-bit wrap-around arithmetic (common/hash.h)."""
    state = (v * 747796405 + 2891336453) & MASK
    word = (((state >> ((state >> 28) + 4)) ^ state) * 277803737) & MASK
    return ((word >> 22) ^ word) & MASK


def pixel_hash(x, y, level):
    return pcg_hash((x + pcg_hash((y + pcg_hash(level)) & MASK)) & MASK)


def rotation_hash(x, y, level, seed):
    """The rotation of level pixel (x, y) under --seed: pixelHash(x, y, level + 4 seed)."""
    return pixel_hash(x, y, (level + 4 * seed) & MASK)


def hash_to_unit(h):
    """The top 24 bits as a float32 in [0, 1)."""
    return F(h >> 8) * F(1.0 / 16777216.0)


def rotation_angle(x, y, level, seed=0):
    return F(6.28318530717958647692) * hash_to_unit(rotation_hash(x, y, level, seed))


def kernel_seed(base, seed):
    return (base + seed * 0x9E3779B9) & MASK


def ssao_kernel(n, seed=SSAO_KERNEL_SEED):
    """common/kernels.cpp ssaoKernel: n points in the unit half-ball, denser near the centre."""
    counter = 0

    def next_unit():
        nonlocal counter
        u = hash_to_unit(pcg_hash((seed + counter) & MASK))
        counter += 1
        return u

    kernel = []
    for i in range(n):
        while True:  # rejection-sample the unit half-ball
            # The order the oracle draws them in: z, then y, then x (its C++ builds the vector
            # from three calls, and GCC evaluates the arguments right to left).
            z = next_unit()
            y = next_unit() * F(2) - F(1)
            x = next_unit() * F(2) - F(1)
            len2 = x * x + y * y + z * z
            if not (len2 > F(1) or len2 < F(1e-4)):
                break
        s = np.sqrt(len2)
        x, y, z = x / s, y / s, z / s
        t = F(i) / F(n)
        scale = F(0.1) + F(0.9) * t * t
        k = scale * (F(0.2) + F(0.8) * next_unit())
        kernel.append((x * k, y * k, z * k))
    return kernel


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    data = json.load(open(sys.argv[1]))
    bad = 0
    for name, base in (("ssao", SSAO_KERNEL_SEED), ("ssgi", SSGI_KERNEL_SEED)):
        given = data["kernels"][name]
        mine = ssao_kernel(given["samples"], kernel_seed(base, data["seed"]))
        wrong = sum(1 for a, b in zip(mine, given["points"]) if [float(v) for v in a] != [F(v) for v in b])
        print(f"mrr_sampling: {name} kernel: {len(mine) - wrong} of {len(mine)} points bit for bit")
        bad += wrong
    vectors = data["rotation_test_vectors"]
    wrong = [v for v in vectors if rotation_hash(v["x"], v["y"], v["level"], v["seed"]) != v["hash"]
             or float(rotation_angle(v["x"], v["y"], v["level"], v["seed"])) != F(v["angle"])]
    print(f"mrr_sampling: rotation hash: {len(vectors) - len(wrong)} of {len(vectors)} test vectors")
    bad += len(wrong)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
