"""Checking: first contacts of a loaded shot, found by the native core."""

from .collision import CollisionResult, find_contacts

__all__ = ["CollisionResult", "find_contacts"]
