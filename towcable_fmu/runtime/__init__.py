"""What the three formulations share: the simulation protocol, the driver of a run (time,
ship motion, set-points, recording), the drive polynomials of the prescribed inputs and
the input kernels."""
