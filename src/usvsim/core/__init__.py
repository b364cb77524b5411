"""Foundations shared by every layer: errors, clock, random streams, frames (numpy only)."""
