"""Readers of RAO files written by hydrodynamic codes, one format per module.

Each reader returns a :class:`ship_motion.rao.RaoTable`: wave frequency [rad/s],
heading [rad] (direction the waves travel from the ship's X axis towards port, 180 deg
= head seas), six complex transfer functions per unit wave amplitude of the ship's CG
([m/m], [rad/m]) with our phase convention (a lead over the wave elevation at the CG,
time factor exp(+i omega t)). Each module's docstring states its source's conventions
and how they are converted (:mod:`.conventions`).

- :mod:`.wamit`: WAMIT's ``.4`` motion output.
- :mod:`.capytaine_dataset`: Capytaine's dataset (netCDF), RAOs by ``capytaine.post_pro.rao``.
- :mod:`.orcaflex`: OrcaFlex vessel-type displacement RAOs (text data file, YAML).
- :meth:`ship_motion.rao.RaoTable.from_csv`: our CSV table.
"""

from .capytaine_dataset import read_capytaine
from .conventions import SourceFrame, mirror_half_range, mirrored, move_to_cg
from .orcaflex import read_orcaflex
from .wamit import read_wamit_4, write_wamit_4

__all__ = ["SourceFrame", "mirror_half_range", "mirrored", "move_to_cg", "read_capytaine", "read_orcaflex",
           "read_wamit_4", "write_wamit_4"]
