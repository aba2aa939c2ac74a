#!/usr/bin/env python3
"""xpixel.py WINDOW X Y [RGB SECONDS]: the colour of pixel X,Y of the X
window WINDOW (an id), read from `xwd -id WINDOW` (faster than ImageMagick
on a loaded machine), printed as R,G,B (0..255). With RGB and SECONDS: poll
until the pixel is RGB, print the seconds it took and exit 0, or print the
last colour and exit 1 after SECONDS."""
import struct
import subprocess
import sys
import time


def grab(window):
    """`xwd -id WINDOW`'s output; tried three times, 0.1 s apart (an X
    server under load may refuse one grab), then xwd's own message."""
    for attempt in range(3):
        run = subprocess.run(['xwd', '-id', window, '-silent'], capture_output=True)
        if run.returncode == 0 and len(run.stdout) >= 100:
            return run.stdout
        time.sleep(0.1)
    raise SystemExit(f'xpixel: xwd -id {window} failed (exit {run.returncode}): '
                     f'{run.stderr.decode(errors="replace").strip()}')


def pixel(window, x, y):
    data = grab(window)
    h = struct.unpack('>25I', data[:100])   # the header is always big-endian
    header_size, width, height = h[0], h[4], h[5]
    byte_order, bpp, bpl = h[7], h[11], h[12]
    masks, ncolors = h[14:17], h[19]
    if not (0 <= x < width and 0 <= y < height):
        raise SystemExit(f'xpixel: {x},{y} outside the {width}x{height} window')
    if bpp != 32:
        raise SystemExit(f'xpixel: {bpp} bits per pixel, only 32 handled')
    off = header_size + 12 * ncolors + y * bpl + 4 * x
    value = struct.unpack('<I' if byte_order == 0 else '>I', data[off:off + 4])[0]
    out = []
    for m in masks:
        shift = (m & -m).bit_length() - 1
        out.append(str((value & m) >> shift))
    return ','.join(out)


def main():
    window, x, y = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    if len(sys.argv) < 6:
        print(pixel(window, x, y))
        return 0
    want, limit = sys.argv[4], float(sys.argv[5])
    start = time.monotonic()
    while True:
        got = pixel(window, x, y)
        took = time.monotonic() - start
        if got == want:
            print(f'{took:.3f}')
            return 0
        if took > limit:
            print(got)
            return 1
        time.sleep(0.01)


if __name__ == '__main__':
    sys.exit(main())
