"""Vortex-induced vibration: wake oscillators coupled to the cable (Westin 2018, appendix A).

* :mod:`.oscillator` — the wake-oscillator equation A19 (as corrected, see there), its
  compiled time stepper and closed forms (Strouhal frequency A25, limit-cycle amplitude);
* :mod:`.loads` — the oscillating drag and lift A20 per node, interpolated linearly along
  the elements and integrated into generalised forces;
* :mod:`.coupling` — the staggered coupling with the cable integrator.

A scene without a ``[viv]`` table builds none of this and pays nothing.
"""

from .oscillator import WakeParameters, limit_cycle_amplitude, strouhal_frequency

__all__ = ["WakeParameters", "limit_cycle_amplitude", "strouhal_frequency"]
