"""Population: the calibration procedure on robots drawn at random."""
