"""Test support: references that share no code with the product (see tight_inclusion.py)."""
