"""Matplotlib for the figure scripts: imported before pyplot, it gives matplotlib a private
config folder (removed at exit: one per run was left in /tmp before) unless MPLCONFIGDIR is set,
and selects the Agg backend, so the scripts run without a display or a writable home.
"""

import atexit
import os
import shutil
import tempfile

if "MPLCONFIGDIR" not in os.environ:
    _config = tempfile.mkdtemp(prefix="pgt_mpl_")
    atexit.register(shutil.rmtree, _config, True)
    os.environ["MPLCONFIGDIR"] = _config

import matplotlib  # noqa: E402

matplotlib.use("Agg")
