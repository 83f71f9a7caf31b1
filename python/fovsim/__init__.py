"""fovsim results in Python (pure Python + numpy; Debian python3-numpy).

    import sys; sys.path.insert(0, "<repo>/python")
    import fovsim
    run = fovsim.load_run("results/quickstart")      # dict: frames, summary, paired, manifest
    tidy = fovsim.long_format(run["frames"], ["config_id", "method", "frame"],
                              ["psnr", "fpsnr", "ssim", "est_ms_total"])

Column names and units: results/README.md; docs/python.md has a worked example.
"""
from .results import (  # noqa: F401
    load_csv,
    load_run,
    load_sweep,
    long_format,
    numeric_columns,
    select,
    to_dataframe,
)

from .engine import Evaluator, overrides_list, run, sweep  # noqa: F401,E402  (compiled part loaded on first use)

__all__ = ["load_csv", "load_run", "load_sweep", "long_format", "numeric_columns", "select", "to_dataframe",
           "run", "sweep",
           "Evaluator", "overrides_list", "FovsimError"]


def __getattr__(name):
    if name == "FovsimError":
        from . import engine

        return engine._module().FovsimError
    raise AttributeError(name)
