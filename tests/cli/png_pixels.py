"""Decodes a PNG of `cdbench picture` with zlib alone, checking what a decoder checks (the
signature, each chunk's CRC, IHDR's format, every row's filter), and prints its size and
pixel counts: `WIDTH HEIGHT drawn=N contact=M`, drawn the pixels not background (white),
contact those of the contact colour (red-orange, however shaded). Where matplotlib is
installed its decoder must read the same pixels."""
import struct
import sys
import zlib

path = sys.argv[1]
data = open(path, "rb").read()
if data[:8] != b"\x89PNG\r\n\x1a\n":
    sys.exit(f"{path}: no PNG signature")
at, chunks = 8, []
while at < len(data):
    length, kind = struct.unpack(">I4s", data[at:at + 8])
    body = data[at + 8:at + 8 + length]
    (crc,) = struct.unpack(">I", data[at + 8 + length:at + 12 + length])
    if zlib.crc32(kind + body) != crc:
        sys.exit(f"{path}: chunk {kind!r}: bad CRC")
    chunks.append((kind, body))
    at += 12 + length
kinds = [k for k, _ in chunks]
if kinds[0] != b"IHDR" or kinds[-1] != b"IEND":
    sys.exit(f"{path}: chunks {kinds}")
width, height, depth, colour, method, filt, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
if (depth, colour, method, filt, interlace) != (8, 2, 0, 0, 0):
    sys.exit(f"{path}: not 8-bit RGB, plain: {(depth, colour, method, filt, interlace)}")
raw = zlib.decompress(b"".join(b for k, b in chunks if k == b"IDAT"))
row = 1 + 3 * width
if len(raw) != row * height:
    sys.exit(f"{path}: {len(raw)} bytes of rows, not {row * height}")
drawn = contact = 0
pixels = []
for y in range(height):
    line = raw[y * row:(y + 1) * row]
    if line[0] != 0:
        sys.exit(f"{path}: row {y}: filter {line[0]}, not 0")
    for x in range(width):
        r, g, b = line[1 + 3 * x:4 + 3 * x]
        pixels.append((r, g, b))
        drawn += (r, g, b) != (255, 255, 255)
        contact += r > 1.5 * g and r > 1.5 * b
try:
    import matplotlib.image
except ImportError:
    pass
else:
    image = matplotlib.image.imread(path)
    if image.shape[:2] != (height, width):
        sys.exit(f"{path}: matplotlib reads {image.shape}")
    for y, x in [(0, 0), (height // 2, width // 2), (height - 1, width - 1)]:
        seen = tuple(int(round(c * 255)) for c in image[y, x][:3])
        if seen != pixels[y * width + x]:
            sys.exit(f"{path}: pixel ({x}, {y}): matplotlib {seen}, zlib {pixels[y * width + x]}")
print(f"{width} {height} drawn={drawn} contact={contact}")
