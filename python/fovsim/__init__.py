"""fovsim in Python: results (numpy; pandas when installed), and through the compiled module
run/sweep/predict/budget and an ask/tell search.

    import fovsim      # after: python3 -m pip install --no-build-isolation --no-index -e python
    run = fovsim.load_run("results/quickstart")      # dict: frames, summary, paired, manifest
    df = fovsim.tidy(run)          # pandas: one row per frame x configuration x metric,
                                   # parameters (sigma, alpha, ...) as columns

Column names and units: results/README.md; docs/python.md has a worked example.
"""
from .results import (  # noqa: F401
    load_csv,
    load_run,
    load_sweep,
    long_format,
    numeric_columns,
    parameter_columns,
    select,
    tidy,
    tidy_sweep,
    to_dataframe,
)

from .engine import AskTell, Evaluator, make_plots, overrides_list, run, sweep  # noqa: F401,E402  (compiled part loaded on first use)
from .cost import budget, predict  # noqa: F401,E402

__all__ = ["load_csv", "load_run", "load_sweep", "long_format", "numeric_columns", "parameter_columns", "select",
           "tidy", "tidy_sweep", "to_dataframe",
           "run", "sweep", "make_plots", "predict", "budget",
           "AskTell", "Evaluator", "overrides_list", "FovsimError", "DEFAULT_DISPLAY", "DEFAULT_GPU"]


def __getattr__(name):
    if name in ("FovsimError", "DEFAULT_DISPLAY", "DEFAULT_GPU"):
        from . import engine

        # The defaults are the library's (kDefaultDisplay, kDefaultGpu), not a second literal.
        return getattr(engine._module(), name)
    raise AttributeError(name)
