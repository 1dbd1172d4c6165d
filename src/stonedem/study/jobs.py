"""Jobs sized to their cost: a study's cases packed into jobs of about JOB_SECONDS of
estimated work, each threshold search one job, and the most expensive jobs first.

Each Snakemake job pays 1.0-1.5 s before its first step (interpreter, xarray, numba, the
first record, Snakemake's preamble; docs/guide/study.md, "Jobs sized to their cost") and the kernels
run 1-10 s per case, so one job per case spends much of a study starting jobs. The plan depends
only on the config (never on -j or on other studies), so a rerun sees the same jobs; a job
whose cases changed reruns, and the case store (stonedem.study.runner) restores its unchanged
cases.
"""

from __future__ import annotations

import copy
import json
from dataclasses import dataclass
from pathlib import Path

from stonedem.study.grid import Case
from stonedem.study.runner import natural_duration

# estimated kernel seconds packed into one job (the estimate runs ~2.3x the measured time)
JOB_SECONDS = 60.0
STEP_SECONDS_PER_BODY = 1.1e-6  # kernel cost of one step per body, point law (measured: 0.7-1.1 us)
# a search runs about this many cases (hunt ~4-7, five bisections, three fills:
# stonedem.study.search)
SEARCH_RUNS = 14


@dataclass(frozen=True)
class Job:
    name: str  # rule name: simulate_<study>_<k> or search_<study>_<k>
    study: str
    cases: tuple  # the cases (a search job: its one system)
    cost: float  # estimated kernel seconds

    @property
    def is_search(self) -> bool:
        return self.cases[0].search is not None


def plan_jobs(
    studies: dict[str, list[Case]],
    records_dir: Path | str = "records",
    job_seconds: float = JOB_SECONDS,
    search_seconds: float = 0.0,
) -> list[Job]:
    """Every study's jobs, the most expensive first (Snakemake priority follows this order).

    ``search_seconds``: threshold searches packed into jobs of about this estimated cost
    (0: one search a job; the IDA's hundreds of short searches share jobs, so a cluster's
    scheduler sees tens of jobs, not hundreds)."""
    estimate = CostEstimate(Path(records_dir))
    jobs = []
    for study, cases in studies.items():
        costs = [estimate(case) for case in cases]
        search = bool(cases) and cases[0].search is not None
        if search:
            costs = [cost * SEARCH_RUNS for cost in costs]
        limit = search_seconds if search else job_seconds
        chunks: list[list] = [[]]
        for case, cost in zip(cases, costs):  # consecutive cases up to the limit each
            if chunks[-1] and sum(c for _, c in chunks[-1]) + cost > limit:
                chunks.append([])
            chunks[-1].append((case, cost))
        kind = "search" if search else "simulate"
        jobs += [
            Job(f"{kind}_{study}_{k}", study, tuple(c for c, _ in chunk), sum(c for _, c in chunk))
            for k, chunk in enumerate(chunks)
            if chunk
        ]
    return sorted(jobs, key=lambda job: -job.cost)


class CostEstimate:
    """Estimated kernel seconds of a case: steps (duration / the automatic dt) x bodies x
    STEP_SECONDS_PER_BODY; scenes and excitations built once each."""

    def __init__(self, records_dir: Path):
        self.records_dir = records_dir
        self.scenes: dict = {}
        self.durations: dict = {}

    def __call__(self, case: Case) -> float:
        spec = copy.deepcopy(case.scene)
        excitation = spec.pop("excitation", None) or {"kind": "none"}
        spec.pop("name", None)
        spec.pop("ensemble", None)  # a member costs what its case does
        solver = spec.get("solver") or {}
        duration = solver.get("duration")
        if duration is None:
            duration = self._natural_duration(excitation)
        key = json.dumps(spec, sort_keys=True, default=repr)
        if key not in self.scenes:
            self.scenes[key] = self._step_cost(spec)
        return duration * self.scenes[key]

    def _step_cost(self, spec: dict) -> float:
        """Kernel seconds per simulated second of a scene (without its excitation)."""
        from stonedem.engine.scene import scene_from_dict
        from stonedem.engine.simulate import choose_time_step

        try:
            solver = {
                **(spec.get("solver") or {}),
                "duration": 1.0,
            }  # the step does not depend on it
            scene = scene_from_dict(
                {**spec, "solver": solver, "excitation": {"kind": "none"}},
                base_dir=self.records_dir,
            )
            dt, _ = choose_time_step(scene)
        except Exception:  # noqa: BLE001 - a bad case is refused by check_config, not here
            return 1.0
        return len(scene.bodies) * STEP_SECONDS_PER_BODY / dt

    def _natural_duration(self, excitation: dict) -> float:
        key = json.dumps(excitation, sort_keys=True, default=repr)
        if key not in self.durations:
            try:
                self.durations[key] = natural_duration(excitation, self.records_dir)
            except Exception:  # noqa: BLE001 - refused by check_config
                self.durations[key] = 10.0
        return self.durations[key]


def job_priority(jobs: list[Job]) -> dict[str, int]:
    """{job name: Snakemake priority}: the costliest job highest, so both cores stay busy
    to the end (longest job first)."""
    return {job.name: len(jobs) - i for i, job in enumerate(jobs)}
