"""Accuracy: where courses and filters end against the truth, and whether courses end at all."""
