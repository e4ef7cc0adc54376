"""What an image file holds, read from its bytes before a pixel is decoded: its size, bit depth
and channels from the PNG, JPEG, BMP or TIFF header, and whether it ends where its format says it
ends. A decoder given a huge or a truncated file either fills the memory or returns a partly
grey image without an error, so both are refused from the header first."""

from __future__ import annotations

import os
import struct
from dataclasses import dataclass

#: Environment variable holding the largest number of pixels an image may have to be decoded.
MAX_PIXELS_VARIABLE = "BLURLOC_MAX_PIXELS"
#: The cap when the variable is not set: 50 megapixels (a 7-Scenes frame has 0.3), 150 MB as
#: 8-bit RGB and 1.2 GB as the float64 copy that the filters work on.
DEFAULT_MAX_PIXELS = 50_000_000

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: PNG colour type -> channels after decoding (a palette expands to RGB).
_PNG_CHANNELS = {0: 1, 2: 3, 3: 3, 4: 2, 6: 4}
#: JPEG start-of-frame markers (baseline, progressive, lossless, arithmetic): not DHT, JPG, DAC.
_JPEG_FRAME_MARKERS = frozenset(range(0xC0, 0xD0)) - {0xC4, 0xC8, 0xCC}
#: JPEG markers that stand alone (no length field): TEM, RST0-7, SOI.
_JPEG_BARE_MARKERS = frozenset([0x01, *range(0xD0, 0xD9)])


@dataclass(frozen=True)
class ImageHeader:
    """Size and layout of an image file, as its header states them.

    Attributes
    ----------
    format : str
        ``PNG``, ``JPEG``, ``BMP`` or ``TIFF``.
    width, height : int
        Pixels.
    bit_depth : int
        Bits per sample (8 or 16 for the images the package writes).
    channels : int
        Samples per pixel after decoding: 1 gray, 2 gray + alpha, 3 colour, 4 colour + alpha.
    complete : bool
        The file holds every byte its structure announces (PNG: the chunks up to ``IEND``;
        JPEG: the end-of-image marker after the first scan; BMP: the file size of its header;
        TIFF: every strip or tile).
    """

    format: str
    width: int
    height: int
    bit_depth: int
    channels: int
    complete: bool

    @property
    def pixels(self) -> int:
        """``width * height``."""
        return self.width * self.height

    def describe(self) -> str:
        """The layout in words, e.g. ``16-bit gray`` or ``8-bit RGB``."""
        kinds = {1: "gray", 2: "gray with alpha", 3: "RGB", 4: "RGBA"}
        return f"{self.bit_depth}-bit {kinds.get(self.channels, f'{self.channels}-channel')}"


def max_pixels() -> int:
    """The pixel cap: :data:`MAX_PIXELS_VARIABLE` if set, else :data:`DEFAULT_MAX_PIXELS`.

    Returns
    -------
    int
        Largest ``width * height`` an image may have to be decoded.

    Raises
    ------
    ValueError
        Naming the variable, when it is set to anything but a positive integer.
    """
    text = os.environ.get(MAX_PIXELS_VARIABLE)
    if text is None:
        return DEFAULT_MAX_PIXELS
    try:
        cap = int(text.replace("_", ""))
    except ValueError:
        cap = 0
    if cap < 1:
        raise ValueError(f"{MAX_PIXELS_VARIABLE}={text!r}: must be a positive whole number of "
                         "pixels")  # fmt: skip
    return cap


def parse_header(data: bytes) -> ImageHeader | None:
    """Read the header of a PNG, JPEG, BMP or TIFF file from its bytes.

    Parameters
    ----------
    data : bytes
        The whole file (its end is needed to tell whether it is complete).

    Returns
    -------
    ImageHeader or None
        None when the bytes start like none of the four formats, or the header itself is cut.
    """
    try:
        if data.startswith(_PNG_SIGNATURE):
            return _png(data)
        if data.startswith(b"\xff\xd8"):
            return _jpeg(data)
        if data.startswith(b"BM"):
            return _bmp(data)
        if data[:4] in (b"II*\x00", b"MM\x00*"):
            return _tiff(data)
    except (struct.error, IndexError):
        return None
    return None


def _png(data: bytes) -> ImageHeader | None:
    """PNG: IHDR is the first chunk; the file is complete when the chunk walk reaches IEND."""
    length, kind = struct.unpack(">I4s", data[8:16])
    if kind != b"IHDR" or length < 13:
        return None
    width, height, depth, colour = struct.unpack(">IIBB", data[16:26])
    position, complete = 8, False
    while position + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[position : position + 8])
        position += 12 + length  # length, type, data, CRC
        if kind == b"IEND":
            complete = position <= len(data)
            break
    channels = _PNG_CHANNELS.get(colour, 3)
    return ImageHeader("PNG", width, height, max(depth, 8), channels, complete)


def _jpeg(data: bytes) -> ImageHeader | None:
    """JPEG: segments up to the first scan; the size is in the start-of-frame segment and the
    file is complete when an end-of-image marker follows the scan (the entropy-coded data
    cannot hold the bytes FF D9)."""
    position, frame = 2, None
    while position + 4 <= len(data):
        if data[position] != 0xFF:
            return None
        marker = data[position + 1]
        if marker == 0xFF:  # fill byte
            position += 1
            continue
        if marker in _JPEG_BARE_MARKERS:
            position += 2
            continue
        (length,) = struct.unpack(">H", data[position + 2 : position + 4])
        if marker in _JPEG_FRAME_MARKERS:
            depth, height, width, channels = struct.unpack(
                ">BHHB", data[position + 4 : position + 10]
            )
            frame = (width, height, depth, channels)
        if marker == 0xDA:  # start of scan
            if frame is None:
                return None
            complete = data.find(b"\xff\xd9", position + 2 + length) >= 0
            return ImageHeader("JPEG", *frame, complete)
        position += 2 + length
    if frame is None:
        return None
    return ImageHeader("JPEG", *frame, complete=False)


def _bmp(data: bytes) -> ImageHeader | None:
    """BMP: the file header states the file size; the info header the size and bits per pixel."""
    (size,) = struct.unpack("<I", data[2:6])
    width, height = struct.unpack("<ii", data[18:26])
    (bits,) = struct.unpack("<H", data[28:30])
    channels = 4 if bits == 32 else 3
    return ImageHeader("BMP", abs(width), abs(height), 8, channels, len(data) >= size)


def _tiff(data: bytes) -> ImageHeader | None:
    """TIFF: the first image file directory; complete when every strip (or tile) is there."""
    order = "<" if data[:2] == b"II" else ">"
    (directory,) = struct.unpack(order + "I", data[4:8])
    (count,) = struct.unpack(order + "H", data[directory : directory + 2])
    tags: dict[int, list[int]] = {}
    for entry in range(count):
        start = directory + 2 + 12 * entry
        tag, kind, number = struct.unpack(order + "HHI", data[start : start + 8])
        if kind not in (3, 4):  # SHORT, LONG: the only types of the tags read here
            continue
        size = 2 if kind == 3 else 4
        where = start + 8 if number * size <= 4 else struct.unpack(
            order + "I", data[start + 8 : start + 12])[0]  # fmt: skip
        code = order + ("H" if kind == 3 else "I") * number
        tags[tag] = list(struct.unpack(code, data[where : where + number * size]))
    if 256 not in tags or 257 not in tags:
        return None
    offsets = tags.get(273, tags.get(324, []))  # strips, else tiles
    lengths = tags.get(279, tags.get(325, []))
    complete = bool(offsets) and all(
        o + n <= len(data) for o, n in zip(offsets, lengths, strict=False)
    )
    depth = tags.get(258, [1])[0]
    channels = tags.get(277, [1])[0]
    return ImageHeader("TIFF", tags[256][0], tags[257][0], depth, channels, complete)
