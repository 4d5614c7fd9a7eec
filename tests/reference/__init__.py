"""Independent reference solutions for the towcable tests (numpy/scipy only; see README.md)."""
