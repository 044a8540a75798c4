"""Does PACER's training give the same weights on another machine? The CPU kernels' instruction set, measured.

A trained PACER model that a fresh checkout cannot rebuild bit for bit forces every stage downstream of it
(PACER's notebooks, the stack) to re-run whenever it is rebuilt (benchmarks/README.md, "PACER's training
across machines"). This script trains the `default` model for a few steps on fixed batches of D_real in
child processes that differ in one setting each, and prints the sha256 of the weights after each run:

- the same settings twice (run-to-run determinism on this machine);
- one torch thread against the profile's two (the reductions' split);
- ATen's generic kernels instead of its AVX2 ones (``ATEN_CPU_CAPABILITY``), oneDNN (the convolutions'
  library) capped at a lower instruction set (``ONEDNN_MAX_CPU_ISA``), and MKL
  (the matrix products') pinned to one code path (``MKL_CBWR``): what differs between two CPUs that is not
  the code, emulated on one machine; the item renderer's OpenCV and NumPy without their AVX2 paths;
  NumPy's OpenBLAS on its generic kernels (``OPENBLAS_CORETYPE``: it picks SkylakeX ones on an AVX-512 CPU,
  Haswell ones on an AVX2 Zen; ``--dataset synthetic`` trains on the items it touches); and the
  pins ``python -m navlab`` sets (``navlab.core.cpu``), which must leave an AVX2 machine's weights as they are.

A setting whose hash differs from the first run changes the trained weights. Needs ``data/`` (``python -m
navlab data build``).
Usage: python benchmarks/pacer_reproducibility.py [--steps 6] [--profile default] [--dataset real]
       [--variants NAME ...]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import subprocess
import sys
import time

from navlab.core.cpu import cpu_flags, pins

VARIANTS = {  # name -> (environment, torch threads or None for the profile's)
    "profile's settings": ({}, None),
    "profile's settings, again": ({}, None),
    "one torch thread": ({}, 1),
    "ATen's generic kernels": ({"ATEN_CPU_CAPABILITY": "default"}, None),
    "oneDNN capped at AVX2": ({"ONEDNN_MAX_CPU_ISA": "AVX2"}, None),
    "oneDNN capped at AVX": ({"ONEDNN_MAX_CPU_ISA": "AVX"}, None),
    "oneDNN capped at SSE4.1": ({"ONEDNN_MAX_CPU_ISA": "SSE41"}, None),
    "MKL pinned to its SSE4.2 path": ({"MKL_CBWR": "SSE4_2"}, None),
    "OpenCV without AVX / AVX2 / FMA3": ({"OPENCV_CPU_DISABLE": "AVX,AVX2,FMA3"}, None),
    "NumPy without AVX2 / FMA3": ({"NPY_DISABLE_CPU_FEATURES": "AVX2 FMA3"}, None),
    "OpenBLAS on its generic kernels": ({"OPENBLAS_CORETYPE": "Prescott"}, None),
    "navlab's pins (python -m navlab)": (pins(cpu_flags(), platform.machine()), None),
    "the pins, OpenBLAS's own kernels": ({name: value for name, value in pins(cpu_flags(), platform.machine()).items()
                                          if name != "OPENBLAS_CORETYPE"}, None),
}


def train_steps(profile: str, data_dir: str, steps: int, threads: int | None, dataset: str = "real") -> dict:
    """``steps`` Adam steps of the profile's model from torch seed 0 on the first training items of
    ``dataset`` (real, shuffled or synthetic: D_synthetic's recolouring multiplies through OpenBLAS);
    the sha256 of the resulting weights and the losses."""
    import torch

    from navlab.core.params import load_params
    from navlab.pacer.datasets import pacer_dataset
    from navlab.pacer.model import build_model
    from navlab.pacer.terrain import load_terrain_bank
    from navlab.pacer.train import ExtraLosses, batch_loss, collate

    params = load_params(profile)
    P = params.pacer
    torch.set_num_threads(threads or P.train.threads)
    bank = load_terrain_bank(data_dir, P.data)
    items = pacer_dataset(params, data_dir, dataset, "train", bank)
    torch.manual_seed(0)
    model = build_model(P.model, context_pairs=P.data.n_pairs, patch_size=P.data.patch_size)
    model = model.to(memory_format=torch.channels_last).train()
    optimiser = torch.optim.Adam(model.parameters(), lr=P.train.lr)  # as pacer.train.train_phase
    size, losses = P.train.batch_size, []
    for step in range(steps):
        loss = batch_loss(model, collate([items[i] for i in range(step * size, (step + 1) * size)]), "cpu",
                          ExtraLosses.of(P.train))
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        losses.append(float(loss))
    digest = hashlib.sha256()
    for name, tensor in sorted(model.state_dict().items()):
        digest.update(name.encode())
        digest.update(tensor.detach().contiguous().numpy().tobytes())
    return {"sha256": digest.hexdigest(), "losses": losses}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=6)
    parser.add_argument("--profile", default="default")
    parser.add_argument("--data", default="data")
    parser.add_argument("--dataset", choices=("real", "shuffled", "synthetic"), default="real",
                        help="the training items (synthetic: the only ones OpenBLAS's kernels touch)")
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS),
                        help="the settings to train under (default: all; the first is the reference)")
    parser.add_argument("--child", type=int, default=None, help=argparse.SUPPRESS)  # threads, in a child run
    args = parser.parse_args()
    if args.child is not None:
        print(json.dumps(train_steps(args.profile, args.data, args.steps, args.child or None, args.dataset)))
        return
    first = None
    for name in args.variants:
        env, threads = VARIANTS[name]
        tic = time.perf_counter()
        out = subprocess.run([sys.executable, __file__, "--steps", str(args.steps), "--profile", args.profile,
                              "--data", args.data, "--dataset", args.dataset, "--child", str(threads or 0)],
                             env={**os.environ, **env}, capture_output=True, text=True, check=True)
        found = json.loads(out.stdout.strip().splitlines()[-1])
        first = first or found
        same = "same weights" if found["sha256"] == first["sha256"] else "OTHER WEIGHTS"
        drift = max(abs(a - b) for a, b in zip(found["losses"], first["losses"]))
        print(f"{name:32s} {found['sha256'][:16]}  {same:13s} max |loss - first run's| {drift:.2e}  "
              f"({time.perf_counter() - tic:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
