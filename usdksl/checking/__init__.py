"""Checking: first contacts of a loaded shot, found by the native core."""
