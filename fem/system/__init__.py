"""The system model of a reducer around the FE contact (docs/stiffness.md)."""
