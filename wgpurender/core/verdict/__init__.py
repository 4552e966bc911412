"""Judging an image: the comparison metrics and the calibrated tolerances of the references."""
