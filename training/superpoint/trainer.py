"""The training loop shared by the two training stages: resumable checkpoints (model, optimiser, step,
configuration), a CSV log, a wall-clock budget, and per-step random generators so that a resumed run
draws the same data as an uninterrupted one. Batches are made on the CPU, optionally by worker
processes (a GPU needs them: rendering and warping would otherwise be the bottleneck)."""
import csv
import json
import os
import time
from pathlib import Path

import numpy as np
import torch


def load_state(path):
    """torch.load of our own checkpoints (PyTorch >= 2.6 defaults to weights_only, which rejects them)."""
    try:
        return torch.load(path, map_location="cpu", weights_only=False)
    except TypeError:                       # PyTorch < 1.13 has no weights_only
        return torch.load(path, map_location="cpu")


class Checkpoint:
    def __init__(self, directory):
        self.directory = Path(directory)
        self.path = self.directory / "checkpoint.pt"

    def exists(self):
        return self.path.is_file()

    def load(self):
        return load_state(self.path)

    def is_finished(self):
        return self.exists() and self.load().get("finished", False)

    def save(self, state):
        self.directory.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name("checkpoint.pt.tmp")
        torch.save(state, tmp)
        os.replace(tmp, self.path)


def step_rng(seed, stage, step, fixed):
    """The generator for one step's data: a function of (seed, stage, step) only, so resume is exact."""
    return np.random.default_rng([seed, stage, 0 if fixed else step])


class StepBatches(torch.utils.data.Dataset):
    """Batch i is make_batch(rng of step start + i): the same batches whichever process makes them."""

    def __init__(self, make_batch, seed, stage, fixed, start, stop):
        self.make_batch, self.seed, self.stage, self.fixed, self.start, self.stop = make_batch, seed, stage, fixed, start, stop

    def __len__(self):
        return max(self.stop - self.start, 0)

    def __getitem__(self, index):
        return self.make_batch(step_rng(self.seed, self.stage, self.start + index, self.fixed))


def _batches(make_batch, seed, stage, fixed, start, stop, workers):
    dataset = StepBatches(make_batch, seed, stage, fixed, start, stop)
    if workers <= 0:
        return (dataset[i] for i in range(len(dataset)))
    return iter(torch.utils.data.DataLoader(dataset, batch_size=None, shuffle=False, num_workers=workers,
                                            prefetch_factor=4, worker_init_fn=_quiet_worker))


def _quiet_worker(_):
    torch.set_num_threads(1)


def run(stage_name, stage_id, model, steps, lr, make_batch, compute_losses, out_dir, config_json, seed, fixed, device,
        checkpoint_every=100, log_every=10, max_minutes=0.0, workers=0, extra_state=None, validate=None, log=print,
        stage_minutes=0.0):
    """Optimises `model` with Adam for `steps` steps from wherever the checkpoint in out_dir left off.

    make_batch(rng) -> CPU tensors (runs in worker processes when workers > 0);
    compute_losses(batch) -> dict of named scalar tensors whose "total" is minimised.
    validate(model) -> dict of progress measures, logged to validation.csv at every checkpoint.
    Returns the list of logged rows (dicts). Stops early, with a checkpoint, when max_minutes is spent.
    stage_minutes > 0 makes the stage a fixed training time instead of a fixed step count: after that many
    minutes of training (summed over resumes) the stage ends as finished, whatever `steps` says.
    """
    out_dir = Path(out_dir)
    checkpoint = Checkpoint(out_dir)
    optimizer = torch.optim.Adam(model.parameters(), lr=lr, betas=(0.9, 0.999))
    step, elapsed = 0, 0.0
    if checkpoint.exists():
        state = checkpoint.load()
        model.load_state_dict(state["model"])
        optimizer.load_state_dict(state["optimizer"])
        step, elapsed = state["step"], state.get("elapsed_s", 0.0)
        if state.get("finished") and (step >= steps or state.get("time_capped")):
            log(f"[{stage_name}] already finished ({step} steps)")
            return []
        log(f"[{stage_name}] resuming at step {step}/{steps}")
        for name in ("log.csv", "validation.csv"):     # rows written after the checkpoint will be redone
            _truncate_csv(out_dir / name, step)
    rows, window, started = [], [], time.time()
    log_path = out_dir / "log.csv"

    def save(finished, time_capped=False):
        if validate is not None:
            row = {"step": step}
            row.update(validate(model))
            _append_csv(out_dir / "validation.csv", row)
            log(f"[{stage_name}] validation " + " ".join(f"{k}={v}" for k, v in row.items()))
        state = {"model": model.state_dict(), "optimizer": optimizer.state_dict(), "step": step,
                 "elapsed_s": elapsed + time.time() - started, "finished": finished, "time_capped": time_capped, "stage": stage_name,
                 "config": json.loads(config_json), "device": str(device)}
        state.update(extra_state or {})
        checkpoint.save(state)

    model.train()
    for batch in _batches(make_batch, seed, stage_id, fixed, step, steps, workers):
        losses = compute_losses(batch)
        optimizer.zero_grad(set_to_none=True)
        losses["total"].backward()
        optimizer.step()
        step += 1
        window.append({k: float(v.detach()) if torch.is_tensor(v) else float(v) for k, v in losses.items()})
        if step % log_every == 0 or step == steps:
            row = {"step": step, "time_s": round(elapsed + time.time() - started, 1)}
            row.update({k: round(float(np.mean([w[k] for w in window])), 5) for k in window[0]})
            window = []
            rows.append(row)
            _append_csv(log_path, row)
            log(f"[{stage_name}] " + " ".join(f"{k}={v}" for k, v in row.items()))
        if step % checkpoint_every == 0 and step < steps:
            save(False)
        if stage_minutes and (elapsed + time.time() - started) / 60 > stage_minutes and step < steps:
            log(f"[{stage_name}] stage time of {stage_minutes} min reached at step {step}: stage finished")
            save(True, time_capped=True)
            return rows
        if max_minutes and (time.time() - started) / 60 > max_minutes and step < steps:
            save(False)
            log(f"[{stage_name}] time budget of {max_minutes} min spent at step {step}; rerun to resume")
            return rows
    save(True)
    return rows


def _truncate_csv(path, last_step):
    if not path.exists():
        return
    lines = path.read_text().splitlines()
    kept = lines[:1] + [line for line in lines[1:] if int(float(line.split(",")[0])) <= last_step]
    path.write_text("\n".join(kept) + "\n")


def _append_csv(path, row):
    path.parent.mkdir(parents=True, exist_ok=True)
    new = not path.exists()
    with open(path, "a", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(row))
        if new:
            writer.writeheader()
        writer.writerow(row)
