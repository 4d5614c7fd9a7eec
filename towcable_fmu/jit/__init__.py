"""Compiled kernels: the on-disk kernel cache, the machine cache (an FMU's code and kernels) and
the parallel compile."""
