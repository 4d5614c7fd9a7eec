"""Parameter sweeps (``towcable sweep``): a TOML spec expanded into cases (:mod:`.spec`),
each case run and reduced to statistics (:mod:`.case`, :mod:`.statistics`), on local
processes or a Dask cluster (:mod:`.execute`), rows appended to one CSV (:mod:`.store`),
plots of the table (:mod:`.plots`)."""

from .execute import SweepReport, run_sweep
from .spec import Case, SpecError, SweepSpec, load_spec
from .statistics import STATISTICS, compute_statistics

__all__ = ["Case", "STATISTICS", "SpecError", "SweepReport", "SweepSpec", "compute_statistics", "load_spec",
           "run_sweep"]
