"""The reducer's datasheet from the FE contact model (docs/stiffness.md): the output twist
against torque in both directions (hysteresis curve, rigidity, lost motion, backlash), the
compliances in series with their shares, the loaded transmission error over the drive's
full period with its harmonics, and the torque split between the members.

``supports``: roller bearings, shafts and the carrier (closed forms); ``twist``: the twist
at one torque along a member's load path; ``sheet``: the hysteresis loop and the
catalogue figures; ``transmission``: the loaded TE over the full period and the split.
"""
