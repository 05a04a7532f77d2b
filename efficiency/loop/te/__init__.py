"""Transmission-error (TE) and hysteresis rig recordings: reading and model-free figures
(installed as ``toothfem.efficiency.loop.te``; docs/te_rig.md).

One job per module:

* :mod:`.columns`: the columns' quantities and units, the operating condition of a run
  (:class:`~.columns.Condition`) from columns, header comments or a file-name pattern;
* :mod:`.recordings`: the files read line by line, each sweep reduced as it ends
  (:func:`~.recordings.read_te_recordings`); a bad file refused in one line, the others
  still read;
* :mod:`.spectrum`: the TE ripple's spectrum in orders of the output revolution, its peaks
  named by a drive's orders (:meth:`toothfem.fem.drives.base.Drive.te_orders`);
* :mod:`.figures`: per condition the forward and backward mean TE and the hysteresis width
  (per-file zero offsets fitted out);
* :mod:`.hysteresis`: a hysteresis staircase recording read, and its catalogue rigidity,
  lost motion, hysteresis loss and backlash by the definitions of
  :mod:`toothfem.fem.datasheet.sheet`;
* :mod:`.synthetic`: recordings with known figures (the tests; the only writer here).
"""
from .columns import Condition  # noqa: F401
from .figures import (ConditionFigures, DirectionFigures, TeFigures,  # noqa: F401
                      te_figures)
from .hysteresis import (HysteresisFigures, HysteresisRecording, HysteresisSet,  # noqa: F401
                         hysteresis_figures, read_hysteresis, read_hysteresis_recordings)
from .recordings import (Refusal, Run, TeRecordings, read_te_file,  # noqa: F401
                         read_te_recordings)
from .spectrum import (Peak, Spectrum, combine_spectra, drive_orders, find_peaks,  # noqa: F401
                       name_peaks, named_peaks, te_spectrum)

__all__ = ["Condition", "ConditionFigures", "DirectionFigures", "HysteresisFigures",
           "HysteresisRecording", "HysteresisSet", "Peak", "Refusal", "Run", "Spectrum",
           "TeFigures", "TeRecordings", "combine_spectra", "drive_orders", "find_peaks",
           "hysteresis_figures", "name_peaks", "named_peaks", "read_hysteresis",
           "read_hysteresis_recordings", "read_te_file", "read_te_recordings", "te_figures",
           "te_spectrum"]
