"""An outside method for tests/cli/extending_tests.sh: reads the OBJ frames `cdbench scenes
generate` writes and writes each frame's pairs of overlapping triangle boxes as
docs/extending.md "Checking an outside method" defines them, with nothing of cdbench.

Usage: outside_pairs.py OBJ_DIR OUT_DIR. Boxes are the min and max of each triangle's
vertices rounded to float (struct's 'f' rounds to nearest, as a C cast does), closed;
pairs are found by a sort on the lower x bound and a sweep, and written larger index
first, in the files pairs0.txt, pairs1.txt, ... (matched to frames in natural order).
"""
import pathlib
import struct
import sys


def to_float(text):
    return struct.unpack("f", struct.pack("f", float(text)))[0]


def boxes_of(obj):
    vertices, boxes = [], []
    for line in obj.read_text().splitlines():
        words = line.split()
        if words and words[0] == "v":
            vertices.append([to_float(w) for w in words[1:4]])
        elif words and words[0] == "f":
            corners = [vertices[int(w.split("/")[0]) - 1] for w in words[1:4]]
            boxes.append(([min(c[a] for c in corners) for a in range(3)],
                          [max(c[a] for c in corners) for a in range(3)]))
    return boxes


def pairs_of(boxes):
    order = sorted(range(len(boxes)), key=lambda i: boxes[i][0][0])
    for s, i in enumerate(order):
        lo, hi = boxes[i]
        for t in range(s + 1, len(order)):
            j = order[t]
            if boxes[j][0][0] > hi[0]:
                break
            if all(boxes[j][0][a] <= hi[a] and lo[a] <= boxes[j][1][a] for a in range(3)):
                yield max(i, j), min(i, j)


def main():
    src, out = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
    out.mkdir(parents=True, exist_ok=True)
    for k, obj in enumerate(sorted(src.glob("frame_*.obj"))):
        with open(out / f"pairs{k}.txt", "w") as w:
            for i, j in pairs_of(boxes_of(obj)):
                w.write(f"{i} {j}\n")


if __name__ == "__main__":
    main()
