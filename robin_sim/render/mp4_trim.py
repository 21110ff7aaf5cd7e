"""Cut a fragmented MP4 back to its last whole fragment (after a write failed mid-fragment).

A fragmented MP4 is a run of top-level boxes: ``ftyp``, ``moov`` (the header), then a
``moof`` + ``mdat`` pair per fragment. When the disk fills up, the last box is cut short and a
decoder stops with an error there; cutting the file back to the end of the last whole
``mdat`` leaves a file that decodes to its end, and frees the space of the torn part.
"""

from __future__ import annotations

import os
import struct
from pathlib import Path

from pil.regular_files import open_regular

HEADER = 8  # a box's 32-bit size and 4-character type
LARGE = 16  # ... plus a 64-bit size when the 32-bit one is 1


def whole_boxes_end(path: str | os.PathLike[str]) -> int:
    """The byte length of ``path``'s leading run of whole top-level boxes, less a trailing
    ``moof`` whose ``mdat`` is missing or cut."""
    size = os.path.getsize(path)
    offset = kept = 0
    last_type = b""
    with open_regular(path) as handle:
        while offset + HEADER <= size:
            handle.seek(offset)
            head = handle.read(LARGE)
            length, kind = struct.unpack(">I4s", head[:HEADER])
            if length == 1 and len(head) == LARGE:
                length = struct.unpack(">Q", head[HEADER:LARGE])[0]
            if length < HEADER or offset + length > size:
                break  # cut short (or size 0: "to the end", never written by the muxer)
            if kind != b"mdat" and last_type == b"moof":
                kept = offset  # a moof not followed by its mdat: drop it
            last_type = kind
            offset += length
            if kind != b"moof":
                kept = offset
    return kept


def trim_torn_tail(path: str | os.PathLike[str]) -> int:
    """Truncate ``path`` to :func:`whole_boxes_end`; the bytes removed."""
    path = Path(path)
    end = whole_boxes_end(path)
    removed = path.stat().st_size - end
    if removed:
        os.truncate(path, end)
    return removed
