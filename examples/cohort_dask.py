"""Map a folder of meshes on a Dask cluster: one task per mesh.

Each mesh NAME.(obj|ply|off|stl) in FOLDER is mapped with demkit (method by topology,
population "area" unless NAME.population.txt beside it gives one value per face); the map is
written beside it as NAME.map.obj with its report NAME.map.json, and one CSV row of every
report's metrics goes to FOLDER/cohort_metrics.csv.

    python examples/cohort_dask.py FOLDER                   # a local cluster of 2 worker processes
    python examples/cohort_dask.py FOLDER --scheduler tcp://scheduler:8786   # a real cluster

Only the Client(...) line differs between the two: the tasks, their inputs and their results
are the same. The workers must see FOLDER (a shared file system) and have demkit installed.
"""

from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

import numpy as np

MESH_SUFFIXES = (".obj", ".ply", ".off", ".stl")
OUTPUT_MARK = ".map."


def meshes_in(folder: Path) -> list[Path]:
    """The input meshes of FOLDER (outputs of an earlier run left out), sorted by name."""
    return sorted(
        p for p in folder.iterdir() if p.suffix.lower() in MESH_SUFFIXES and OUTPUT_MARK not in p.name
    )


def map_one(path: str, options: dict | None = None) -> dict:
    """Map one mesh file, write NAME.map.obj and NAME.map.json beside it; return its report."""
    import demkit

    path = Path(path)
    v, f = demkit.read_mesh(path)
    population_file = path.with_suffix(".population.txt")
    population = "area"
    if population_file.exists():
        population = np.loadtxt(population_file, comments="#", ndmin=1)
    m = demkit.map(v, f, population=population, **(options or {}))
    out = path.with_name(path.stem + ".map.obj")
    demkit.write_mesh(out, m.vertices, m.faces)
    report = dict(m.report)
    out.with_suffix(".json").write_text(json.dumps(report, indent=2) + "\n")
    return {"mesh": path.name, "output": out.name, **report}


def write_csv(reports: list[dict], path: Path) -> None:
    """One row per mesh: name, method, convergence, iterations, times and every metric."""
    fields = ["mesh", "method", "vertices", "faces", "converged", "stop_reason", "iterations", "time_s"]
    metric_names = list(reports[0]["metrics"]) if reports else []
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(fields + metric_names)
        for r in reports:
            w.writerow(
                [r["mesh"], r["method"], r["input"]["vertices"], r["input"]["faces"], r["converged"],
                 r["stop_reason"], r["iterations"], r["time_s"]["total"]]
                + [r["metrics"][k] for k in metric_names]
            )


def run(folder: Path, client, options: dict | None = None) -> list[dict]:
    """Map every mesh of FOLDER on the Dask `client`, one task per mesh; write the CSV."""
    paths = [str(p) for p in meshes_in(folder)]
    futures = client.map(map_one, paths, options=options, pure=False)
    reports = client.gather(futures)
    write_csv(reports, folder / "cohort_metrics.csv")
    return reports


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder", type=Path)
    parser.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local cluster)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of the local cluster")
    a = parser.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    if a.scheduler:
        client = Client(a.scheduler)
    else:
        client = Client(LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True))
    t0 = time.perf_counter()
    with client:
        reports = run(a.folder, client)
    wall = time.perf_counter() - t0
    for r in reports:
        print(f"{r['mesh']}: {r['method']}, {r['iterations']} iterations, "
              f"density error {r['metrics']['density_error_mean']:.4f}, {r['time_s']['total']:.2f} s")
    print(f"{len(reports)} meshes in {wall:.2f} s; metrics in {a.folder / 'cohort_metrics.csv'}")
    return 0 if all(r["converged"] for r in reports) else 3


if __name__ == "__main__":
    sys.exit(main())
