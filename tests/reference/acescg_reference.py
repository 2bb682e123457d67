#!/usr/bin/env python3
"""ACEScg (linear AP1) -> linear Rec.709, derived from the chromaticities (standard library).

The expected colour of tests/unit/test_materialx.cpp
(Materialx.AcescgColoursAreConvertedToLinearRec709), written from the definitions and not
from gonio's matrix:
- AP1 primaries R (0.713, 0.293), G (0.165, 0.830), B (0.128, 0.044), white D60
  (0.32168, 0.33767): SMPTE ST 2065-1 / ACES S-2014-004 (ACEScg).
- BT.709 primaries R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06), white D65
  (0.3127, 0.3290): ITU-R BT.709-6.
- RGB -> XYZ: the primaries' XYZ scaled so that RGB (1, 1, 1) is the white (Y = 1).
- White adaptation D60 -> D65: von Kries in the CAT02 cone space (CIECAM02), as
  MaterialX's M_AP1_TO_REC709 (mx_transform_color.glsl) does.
Run: python3 tests/reference/acescg_reference.py
"""


def xyz(x, y):
    return [x / y, 1.0, (1 - x - y) / y]


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def inverse(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [[(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
            [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
            [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det]]


def rgb_to_xyz(primaries, white):
    p = [xyz(*c) for c in primaries]
    cols = [[p[j][i] for j in range(3)] for i in range(3)]  # primaries as columns
    s = mat_vec(inverse(cols), xyz(*white))
    return [[cols[i][j] * s[j] for j in range(3)] for i in range(3)]


CAT02 = [[0.7328, 0.4296, -0.1624], [-0.7036, 1.6975, 0.0061], [0.0030, 0.0136, 0.9834]]
AP1, D60 = [(0.713, 0.293), (0.165, 0.830), (0.128, 0.044)], (0.32168, 0.33767)
REC709, D65 = [(0.64, 0.33), (0.30, 0.60), (0.15, 0.06)], (0.3127, 0.3290)

src, dst = mat_vec(CAT02, xyz(*D60)), mat_vec(CAT02, xyz(*D65))
adapt = mat_mul(inverse(CAT02), mat_mul([[dst[i] / src[i] if i == j else 0.0 for j in range(3)] for i in range(3)], CAT02))
M = mat_mul(inverse(rgb_to_xyz(REC709, D65)), mat_mul(adapt, rgb_to_xyz(AP1, D60)))

if __name__ == "__main__":
    for row in M:
        print(" ".join(f"{v:.10f}" for v in row))
    print("acescg (0.5, 0.25, 0.125) ->", ", ".join(f"{v:.10f}" for v in mat_vec(M, [0.5, 0.25, 0.125])))
