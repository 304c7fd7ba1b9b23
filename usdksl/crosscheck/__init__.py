"""Cross-check: static frames intersected with Embree, held against the continuous result."""

from .shot import CrosscheckResult, crosscheck_csv_path, crosscheck_shot

__all__ = ["CrosscheckResult", "crosscheck_csv_path", "crosscheck_shot"]
