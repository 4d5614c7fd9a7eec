"""towcable: marine towed-cable simulator (ANCF cable, winch, sheave, towed body) for FMI co-simulation."""

from ._kernel_cache import refresh_stale_cache

refresh_stale_cache()
