"""The hand tracker's files, served by the live server itself (no external URL).

From the npm package ``@mediapipe/hands`` 0.4.1675469240 (Apache-2.0, ``static/vendor/LICENSE``),
only what Chromium with WebAssembly SIMD loads for ``modelComplexity: 1``.
"""

from __future__ import annotations

from pathlib import Path

VENDOR_DIR = Path(__file__).resolve().parent.parent / "static" / "vendor"
PACKAGE = "@mediapipe/hands"
TRACKER_VERSION = "0.4.1675469240"
VENDOR_TYPES: dict[str, str] = {  # all /static/vendor/ serves, by exact name
    "hands.js": "text/javascript",
    "hands_solution_packed_assets_loader.js": "text/javascript",
    "hands_solution_simd_wasm_bin.js": "text/javascript",
    "hands_solution_simd_wasm_bin.wasm": "application/wasm",
    "hands_solution_packed_assets.data": "application/octet-stream",
    "hands.binarypb": "application/octet-stream",
    "hand_landmark_full.tflite": "application/octet-stream",
}
TEXT_TYPES = ("text/javascript",)
