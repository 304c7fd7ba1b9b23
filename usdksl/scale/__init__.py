"""Running at scale: many shots in one call, on this process or a Dask cluster; farm chunks merged."""

from .batch import ShotJob, ShotOutcome, expand_shots, make_jobs, run_batch, run_job

__all__ = ["ShotJob", "ShotOutcome", "expand_shots", "make_jobs", "run_batch", "run_job"]
