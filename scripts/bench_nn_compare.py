#!/usr/bin/env python3
"""C++ (build/bin/bench_nn) versus PyTorch in Python (training/pllvo_nets), side by side.

    python3 scripts/bench_nn_compare.py [--bench build/bin/bench_nn] [--repetitions 5] [--rounds 2]

For every workload (SuperPoint 752x480 / 376x240, LightGlue 512 / 1024 keypoints with
adaptivity off / on, mutual nearest neighbours, a 1024x512x512 sgemm) and 1 and 2 threads,
the C++ benchmark and the same computation in Python run one after the other, each
`--repetitions` single calls after a warm-up call; the whole sequence is repeated `--rounds`
times. Reported: median wall time, median process CPU time (all threads) and the ratio
Python / C++ (> 1: C++ faster). On a shared machine, wall times follow the load; the ratios
of neighbouring runs and the CPU times are the figures to read.

Both sides set LibTorch's and OpenBLAS's thread counts together. OMP_WAIT_POLICY
(default PASSIVE, see docs/nn.md) is set for both before LibTorch loads.
"""
import argparse
import ctypes
import ctypes.util
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, ".."))


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bench", default=os.path.join(ROOT, "build", "bin", "bench_nn"))
    parser.add_argument("--shared", default=os.environ.get("PLLVO_SHARED", os.path.join(ROOT, "..", "shared")))
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--threads", default="1,2")
    parser.add_argument("--omp-wait-policy", default="PASSIVE", help="PASSIVE, ACTIVE or 'default' (unset)")
    parser.add_argument("--filter", default="", help="only workloads whose name contains this")
    parser.add_argument("--python-malloc", choices=["default", "tuned"], default="default",
                        help="tuned: run the Python side with the glibc settings of nn::keep_freed_memory() "
                             "(MALLOC_MMAP_MAX_=0 ...), which the C++ benchmark uses")
    parser.add_argument("--json", help="write all measurements here")
    return parser.parse_args()


ARGS = parse_args()
MALLOC_TUNING = {"MALLOC_MMAP_MAX_": "0", "MALLOC_TRIM_THRESHOLD_": str(1 << 30), "MALLOC_TOP_PAD_": str(64 << 20)}
if ARGS.python_malloc == "tuned" and os.environ.get("MALLOC_MMAP_MAX_") != "0":
    # glibc reads these when the process starts: re-run this script with them.
    os.execve(sys.executable, [sys.executable] + sys.argv, {**os.environ, **MALLOC_TUNING})
if ARGS.omp_wait_policy != "default":
    os.environ["OMP_WAIT_POLICY"] = ARGS.omp_wait_policy  # before torch loads libgomp
else:
    os.environ.pop("OMP_WAIT_POLICY", None)

import numpy as np  # noqa: E402
import torch  # noqa: E402
import torch.nn.functional as F  # noqa: E402

sys.path.insert(0, os.path.join(ROOT, "training"))
from pllvo_nets.image_io import read_png  # noqa: E402
from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict  # noqa: E402
from pllvo_nets.mnn import mutual_nn_match  # noqa: E402
from pllvo_nets.safetensors_io import load_safetensors  # noqa: E402
from pllvo_nets.superpoint import SuperPoint  # noqa: E402

torch.set_grad_enabled(False)


# --- runtime ---------------------------------------------------------------------------

def _openblas():
    for name in ("openblas", "blas"):
        path = ctypes.util.find_library(name)
        try:
            lib = ctypes.CDLL(path) if path else None
            if lib is not None and hasattr(lib, "openblas_set_num_threads"):
                return lib
        except OSError:
            pass
    return None


OPENBLAS = _openblas()


def set_threads(n):
    torch.set_num_threads(n)
    if OPENBLAS is not None:
        OPENBLAS.openblas_set_num_threads(n)


def blas_provider():
    """The library serving sgemm_ in this process (dladdr), as bench_nn reports for C++."""

    class DlInfo(ctypes.Structure):
        _fields_ = [("dli_fname", ctypes.c_char_p), ("dli_fbase", ctypes.c_void_p),
                    ("dli_sname", ctypes.c_char_p), ("dli_saddr", ctypes.c_void_p)]

    libdl = ctypes.CDLL(None)
    libdl.dlsym.restype = ctypes.c_void_p
    libdl.dlsym.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
    address = libdl.dlsym(None, b"sgemm_")
    info = DlInfo()
    if address and libdl.dladdr(ctypes.c_void_p(address), ctypes.byref(info)):
        return info.dli_fname.decode()
    with open("/proc/self/maps") as maps:  # fallback: the BLAS libraries mapped
        libs = {line.split()[-1] for line in maps if "blas" in line or "atlas" in line}
    return "not in the global scope; mapped: " + ", ".join(sorted(libs))


# --- the Python side of each workload ----------------------------------------------------

def tensors(path):
    values, meta = load_safetensors(path)
    return {k: torch.from_numpy(v.astype(np.float32) if v.dtype == np.float16 else v) for k, v in values.items()}, meta


class PythonWorkloads:
    def __init__(self, shared):
        sp_dir = os.path.join(shared, "testvectors", "superpoint")
        lg_dir = os.path.join(shared, "testvectors", "lightglue")
        image = torch.from_numpy(read_png(os.path.join(sp_dir, "sacre_coeur1_752x480.png"))).float()[None, None]
        self.images = {752: image / 255, 376: F.avg_pool2d(image, 2).round() / 255}  # = cv::INTER_AREA at 1/2
        self.superpoint = SuperPoint(detection_threshold=0.0005).eval()
        self.superpoint.load_state_dict(tensors(os.path.join(shared, "models", "superpoint_v1.safetensors"))[0])

        random_sp, _ = tensors(os.path.join(sp_dir, "superpoint_random_weights.safetensors"))
        self.pairs = {}
        for k in (512, 1024):
            net = SuperPoint(detection_threshold=0.0, max_num_keypoints=k).eval()
            net.load_state_dict(random_sp)
            feats = []
            for name in ("icl250_640x480", "icl254_640x480"):
                img = torch.from_numpy(read_png(os.path.join(sp_dir, name + ".png"))).float()[None, None] / 255
                out = net(img)
                feats.append({"keypoints": out["keypoints"][0][None], "descriptors": out["descriptors"][0][None],
                              "image_size": torch.tensor([[640.0, 480.0]])})
            self.pairs[k] = feats

        base, _ = tensors(os.path.join(lg_dir, "lightglue_sp_random_l9_d256.safetensors"))
        override, _ = tensors(os.path.join(lg_dir, "lightglue_sp_random_l9_d256_b_token_confidence.safetensors"))
        self.lightglue = {}
        for adaptive, state in ((0, base), (1, {**base, **override})):
            net = LightGlue(**lightglue_conf_from_state_dict(state),
                            depth_confidence=0.6 if adaptive else -1, width_confidence=0.25 if adaptive else -1).eval()
            net.load_state_dict(state)
            self.lightglue[adaptive] = net
        self.a, self.b = torch.randn(1024, 512), torch.randn(512, 512)

    def call(self, kind, params):
        """Runs one call; returns the counters the C++ benchmark reports."""
        if kind == "SuperPoint":
            out = self.superpoint(self.images[params["width"]])
            return {"keypoints": len(out["keypoints"][0])}
        if kind == "LightGlue":
            f0, f1 = self.pairs[params["keypoints"]]
            out = self.lightglue[params["adaptive"]](f0, f1)
            return {"stop": out["stop"], "matches": len(out["matches"])}
        if kind == "Mnn":
            f0, f1 = self.pairs[params["keypoints"]]
            matches, _ = mutual_nn_match(f0["descriptors"][0], f1["descriptors"][0])
            return {"matches": len(matches)}
        if kind == "SgemmTorch":
            torch.mm(self.a, self.b)
            return {}
        raise ValueError(kind)


# --- measuring ---------------------------------------------------------------------------

WORKLOADS = (
    [("SuperPoint", {"width": w}) for w in (752, 376)]
    + [("LightGlue", {"keypoints": k, "adaptive": a}) for k in (512, 1024) for a in (0, 1)]
    + [("Mnn", {"keypoints": k}) for k in (512, 1024)]
    + [("SgemmTorch", {})]
)


def bench_name(kind, params, threads):
    parts = [f"BM_{kind}"] + [f"{k}:{v}" for k, v in params.items()] + [f"threads:{threads}"]
    return "/".join(parts)


def run_cpp(kind, params, threads, repetitions):
    name = bench_name(kind, params, threads)
    with tempfile.NamedTemporaryFile(suffix=".json") as result:
        cmd = [ARGS.bench, f"--benchmark_filter=^{name}/", f"--benchmark_repetitions={repetitions}",
               f"--benchmark_out={result.name}", "--benchmark_out_format=json"]
        env = {k: v for k, v in os.environ.items() if k not in MALLOC_TUNING}  # C++ tunes itself
        out = subprocess.run(cmd, capture_output=True, text=True, check=True, env=env)
        report = json.load(open(result.name))
    runs = [b for b in report["benchmarks"] if b.get("run_type") == "iteration"]
    if not runs:
        raise RuntimeError(f"{name}: no runs ({out.stderr.strip()})")
    scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6}[runs[0]["time_unit"]]
    wall = [r["real_time"] * scale for r in runs]
    cpu = [r["cpu_time"] * scale for r in runs]
    counters = {k: runs[0][k] for k in ("keypoints", "stop", "matches", "pruned_share") if k in runs[0]}
    return wall, cpu, counters, report["context"]


def run_python(workloads, kind, params, threads, repetitions):
    set_threads(threads)
    counters = workloads.call(kind, params)  # warm-up
    iterations = 10 if kind == "SgemmTorch" else 1  # as the C++ benchmark
    wall, cpu = [], []
    for _ in range(repetitions):
        t0, c0 = time.perf_counter(), time.process_time()
        for _ in range(iterations):
            workloads.call(kind, params)
        wall.append((time.perf_counter() - t0) * 1e3 / iterations)
        cpu.append((time.process_time() - c0) * 1e3 / iterations)
    return wall, cpu, counters


def main():
    threads_list = [int(t) for t in ARGS.threads.split(",")]
    print(f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', '(unset)')}; torch {torch.__version__}; "
          f"Python malloc: {ARGS.python_malloc}")
    print(f"Python sgemm_ provider: {blas_provider()}")
    workloads = PythonWorkloads(ARGS.shared)
    results = {}
    context_printed = False
    for _ in range(ARGS.rounds):
        for threads in threads_list:
            for kind, params in WORKLOADS:
                name = bench_name(kind, params, threads)
                if ARGS.filter and ARGS.filter not in name:
                    continue
                reps = max(2, ARGS.repetitions // 2) if (kind == "LightGlue" and params["keypoints"] == 1024
                                                         and not params["adaptive"]) else ARGS.repetitions
                cw, cc, ccount, context = run_cpp(kind, params, threads, reps)
                if not context_printed:
                    print(f"C++ sgemm_ provider: {context.get('sgemm_provider')}; load average {context.get('load_avg')}")
                    context_printed = True
                pw, pc, pcount = run_python(workloads, kind, params, threads, reps)
                r = results.setdefault(name, {"cpp_wall": [], "cpp_cpu": [], "py_wall": [], "py_cpu": []})
                r["cpp_wall"] += cw
                r["cpp_cpu"] += cc
                r["py_wall"] += pw
                r["py_cpu"] += pc
                r["cpp_counters"], r["py_counters"] = ccount, pcount
                print(f"  {name}: C++ {statistics.median(cw):.1f} ms, Python {statistics.median(pw):.1f} ms", flush=True)

    header = f"{'workload':58s} {'C++ wall':>9s} {'Py wall':>9s} {'ratio':>6s} {'C++ cpu':>9s} {'Py cpu':>9s} {'ratio':>6s}  counters (C++ | Python)"
    print("\nmedians in ms; ratio = Python / C++ (> 1: C++ faster)")
    print(header)
    for name, r in results.items():
        m = {k: statistics.median(v) for k, v in r.items() if k.endswith(("wall", "cpu"))}
        print(f"{name:58s} {m['cpp_wall']:9.1f} {m['py_wall']:9.1f} {m['py_wall'] / m['cpp_wall']:6.2f} "
              f"{m['cpp_cpu']:9.1f} {m['py_cpu']:9.1f} {m['py_cpu'] / m['cpp_cpu']:6.2f}  "
              f"{r['cpp_counters']} | {r['py_counters']}")
    if ARGS.json:
        with open(ARGS.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
