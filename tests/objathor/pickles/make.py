"""Writes the reference pickles of tests/objathor.rs: the same dict (a list of uids and two
float16 arrays, shaped like objathor's clip_features.pkl) with protocols 2 to 5.

Also the same dict with float32 arrays (`clip_<tag>_f32_p<protocol>.pkl`: a folder whose features
were re-saved as float32).

Run once with numpy 1 (`python make.py np1`: module names `numpy.core.…`) and once with
numpy 2 (`python make.py np2`: `numpy._core.…`); the eight files are committed.
"""

import pickle
import sys

import numpy as np

tag = sys.argv[1]
img = np.array(
    [[[0.5, -0.25, 1.0], [0.0, 2.0, -1.5]], [[65504.0, 6.1e-05, -0.0], [1.0 / 3, 0.1, 1e-7]]],
    dtype=np.float16,
)
txt = np.array([[1.0, 2.0, 3.0], [-4.0, 0.5, 0.125]], dtype=np.float16)
obj = {"uids": ["a" * 32, "b" * 32], "img_features": img, "text_features": txt}
for p in (2, 3, 4, 5):
    with open(f"clip_{tag}_p{p}.pkl", "wb") as f:
        pickle.dump(obj, f, protocol=p)
obj32 = {
    "uids": obj["uids"],
    "img_features": img.astype(np.float32),
    "text_features": txt.astype(np.float32),
}
for p in (2, 5):
    with open(f"clip_{tag}_f32_p{p}.pkl", "wb") as f:
        pickle.dump(obj32, f, protocol=p)
