"""Rope life: tension fatigue (rainflow and T-N curves), bending cycles over the sheave
and drum along the rope, and the extremes of a tension (docs/design.md, "Rope life")."""
