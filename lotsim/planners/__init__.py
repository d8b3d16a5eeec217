"""Planners: parking maneuvers and cooperative multi-vehicle search (later issues)."""
