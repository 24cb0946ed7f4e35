"""A recording opened safely, and a WAV file's header read and checked without FFmpeg.

`open_recording` opens without blocking and looks at what it opened, so a
file swapped for a FIFO or a device after it was checked is refused at once
rather than waited on. `wav_header` reads a RIFF WAVE header with the
standard library: `check` (with or without PyAV) and `render` both pass every
WAV through it, so a recording one refuses the other refuses too, with the
same words, and FFmpeg never meets a header that would send it scanning
through hundreds of megabytes.
"""

from __future__ import annotations

import os
import stat
import struct
from typing import BinaryIO, NamedTuple, Optional

# The format tags FFmpeg decodes that a WAV recording is likely to hold; the rest are refused by name.
FORMATS = {
    0x0001: "PCM",
    0x0002: "MS ADPCM",
    0x0003: "IEEE float",
    0x0006: "A-law",
    0x0007: "mu-law",
    0x0011: "IMA ADPCM",
    0x0031: "GSM 6.10",
    0x0055: "MP3",
    0xFFFE: "extensible",
}
UNCOMPRESSED = (0x0001, 0x0003, 0x0006, 0x0007)
MAX_CHANNELS = 32
MAX_RATE = 768_000
HEAD_CHUNKS = 64  # chunks looked through for `fmt ` and `data`: a file of empty chunks is not sound


class HeaderError(ValueError):
    """A file that is not a recording we read; the message says why, without the file's name."""


class WavHeader(NamedTuple):
    format_tag: int
    channels: int
    rate: int
    bits: int
    byte_rate: int
    block_align: int
    data_bytes: int  # what the data chunk holds, as far as the file goes

    @property
    def seconds(self) -> float:
        return self.data_bytes / self.byte_rate


def open_recording(path: str) -> BinaryIO:
    """`path` opened for reading: a regular file, whatever it was when it was checked.

    O_NONBLOCK makes opening a FIFO (or a device) return at once instead of waiting for a
    writer; what was opened is then looked at through its descriptor, so no name swapped
    in between can fool it. HeaderError otherwise.
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    flags |= getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        raise HeaderError("no such file") from None
    except OSError as e:
        raise HeaderError((e.strerror or str(e)).lower()) from None
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            raise HeaderError("not a file")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def is_wav(head: bytes) -> bool:
    return len(head) >= 12 and head[:4] in (b"RIFF", b"RIFX", b"RF64") and head[8:12] == b"WAVE"


def wav_header(file: BinaryIO) -> Optional[WavHeader]:
    """The header of the WAV file `file` (at its start), checked; None if it is not a WAV file.

    HeaderError for one that cannot be played: no channels, no bits, a format tag FFmpeg
    would not decode as sound, no `data` chunk, or a length it does not hold.
    """
    size = os.fstat(file.fileno()).st_size
    head = file.read(12)
    if not is_wav(head):
        return None
    if head[:4] != b"RIFF":
        raise HeaderError(f"a {head[:4].decode('ascii')} WAV file, which is not read: save it as RIFF WAV")
    fmt: Optional[bytes] = None
    for _ in range(HEAD_CHUNKS):
        chunk = file.read(8)
        if len(chunk) < 8:
            break
        name, length = chunk[:4], struct.unpack("<I", chunk[4:])[0]
        if name == b"fmt ":
            if not 16 <= length <= 4096:
                raise HeaderError(f"a WAV file whose format chunk is {length} bytes long")
            fmt = file.read(length)
        elif name == b"data":
            if fmt is None:
                raise HeaderError("a WAV file whose sound comes before its format")
            held = max(0, size - file.tell())
            return _checked(fmt, min(length, held))
        else:
            file.seek(length + (length & 1), os.SEEK_CUR)
    if fmt is None:
        raise HeaderError("a WAV file with no format chunk")
    raise HeaderError("a WAV file with no sound (no data chunk)")


def _checked(fmt: bytes, data_bytes: int) -> WavHeader:
    if len(fmt) < 16:
        raise HeaderError("a WAV file whose format chunk is cut short")
    tag, channels, rate, byte_rate, block_align, bits = struct.unpack("<HHIIHH", fmt[:16])
    if tag == 0xFFFE and len(fmt) >= 26:
        tag = struct.unpack("<H", fmt[24:26])[0]  # the sub-format's GUID starts with the real tag
    if tag not in FORMATS or tag == 0xFFFE:
        raise HeaderError(f"a WAV file of format tag 0x{tag:04x}, which is not sound FFmpeg reads")
    if not 1 <= channels <= MAX_CHANNELS:
        raise HeaderError(f"a WAV file of {channels} channels (1 to {MAX_CHANNELS} are read)")
    if not 1 <= rate <= MAX_RATE:
        raise HeaderError(f"a WAV file of {rate} samples a second")
    if tag in UNCOMPRESSED:
        if bits == 0 or bits > 64 or block_align < channels * ((bits + 7) // 8):
            raise HeaderError(f"a WAV file of {bits}-bit samples in {block_align}-byte blocks")
        byte_rate = rate * block_align  # what the data holds, whatever the header claims
    if byte_rate <= 0 or block_align <= 0:
        raise HeaderError("a WAV file that says it holds no bytes a second")
    if data_bytes < block_align:
        raise HeaderError("a WAV file with no sound (an empty data chunk)")
    return WavHeader(tag, channels, rate, bits, byte_rate, block_align, data_bytes)
