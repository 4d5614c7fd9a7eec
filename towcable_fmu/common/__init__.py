"""What every part of towcable shares: errors, the schema mechanism, the variable contract,
run files and plots of a run."""
