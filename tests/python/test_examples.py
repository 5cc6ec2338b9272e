"""The examples run headless (matplotlib Agg) and write a figure with something on it."""
import os
import subprocess
import sys

import numpy as np

from conftest import SOURCE_DIR


def test_robot_path_phase_rssi(tmp_path):
    out = tmp_path / "phase_rssi.png"
    script = SOURCE_DIR / "python" / "examples" / "robot_path_phase_rssi.py"
    proc = subprocess.run([sys.executable, str(script), "--duration", "30", "-o", str(out)], capture_output=True,
                          text=True, timeout=240, env={**os.environ, "MPLBACKEND": "Agg"})
    assert proc.returncode == 0, proc.stderr
    assert "ideal:" in proc.stdout and "single-bounce:" in proc.stdout
    import matplotlib.image
    img = matplotlib.image.imread(str(out))
    assert img.shape[0] > 400 and img.shape[1] > 600
    # Both series drawn: pixels of each line colour exist.
    rgb = (img[..., :3] * 255).astype(int)
    for colour in ((0x1F, 0x77, 0xB4), (0xD6, 0x27, 0x28)):
        assert (np.abs(rgb - colour).sum(axis=2) < 30).sum() > 50, colour
