"""Friction laws and gear-train power flow (installed as ``toothfem.efficiency``)."""
