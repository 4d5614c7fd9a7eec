"""towcable: marine towed-cable simulator (ANCF cable, winch, sheave, towed body) for FMI co-simulation."""

from .kernel_cache import install as _install_kernel_cache

_install_kernel_cache()  # before any kernel module is imported: numba picks the cache locator at decoration
