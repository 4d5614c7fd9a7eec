"""Hydrodynamics: loading functions, current and turbulence, cable and towed-body loads."""
