"""towcable: marine towed-cable simulator (ANCF cable, winch, sheave, towed body) for FMI co-simulation."""
