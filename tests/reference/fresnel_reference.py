#!/usr/bin/env python3
"""Independent reference values for tests/unit/test_fresnel.cpp.

Written separately from the C++ code and with different formulas: dielectrics through
Snell's law in angles (Hecht, Optics §4.6: r_s = -sin(θi-θt)/sin(θi+θt),
r_p = tan(θi-θt)/tan(θi+θt)), conductors through the real a², b² form of the complex
Fresnel equations (Born & Wolf §14.2; the form pbrt-v3 used):
  a²+b² = sqrt((n²-k²-sin²θ)² + 4n²k²),  a = sqrt((a²+b² + n²-k²-sin²θ)/2)
  Rs = (a²+b² - 2a cosθ + cos²θ) / (a²+b² + 2a cosθ + cos²θ)
  Rp = Rs (cos²θ(a²+b²) - 2a cosθ sin²θ + sin⁴θ) / (cos²θ(a²+b²) + 2a cosθ sin²θ + sin⁴θ)
Run it to print the values the tests hard-code.
"""
import math

def dielectric(theta_deg, eta):
    ti = math.radians(theta_deg)
    st = math.sin(ti) / eta
    if st >= 1:
        return 1.0, 1.0
    tt = math.asin(st)
    if theta_deg == 0:
        r = ((eta - 1) / (eta + 1)) ** 2
        return r, r
    rs = -math.sin(ti - tt) / math.sin(ti + tt)
    rp = math.tan(ti - tt) / math.tan(ti + tt)
    return rs * rs, rp * rp

def conductor(theta_deg, n, k):
    t = math.radians(theta_deg)
    c, s = math.cos(t), math.sin(t)
    s2 = s * s
    t0 = n * n - k * k - s2
    a2b2 = math.sqrt(t0 * t0 + 4 * n * n * k * k)
    a = math.sqrt(max(0.0, (a2b2 + t0) / 2))
    rs = (a2b2 - 2 * a * c + c * c) / (a2b2 + 2 * a * c + c * c)
    num = c * c * a2b2 - 2 * a * c * s2 + s2 * s2
    den = c * c * a2b2 + 2 * a * c * s2 + s2 * s2
    rp = rs * num / den
    return rs, rp

if __name__ == "__main__":
    for eta in (1.5, 1.333, 1 / 1.5, 2.4):
        for th in (0, 10, 30, 45, 60, 75, 80, 89):
            rs, rp = dielectric(th, eta)
            print(f"dielectric eta={eta:.17g} theta={th}: Rs={rs:.12f} Rp={rp:.12f} R={(rs+rp)/2:.12f}")
    for name, n, k in (("Au g", 0.3504, 2.7141), ("Au r", 0.1678, 3.1378), ("Al b", 0.618, 5.4694),
                       ("Cu r", 0.2166, 3.6377),
                       # RGB-mode named gold, red and green (models_reference.metal_index("Au"),
                       # to float precision): F0 = 0.999 and 0.7825.
                       ("Au RGB r", 0.167789326, 25.8803704), ("Au RGB g", 0.350409967, 2.14983999)):
        for th in (0, 30, 60, 80, 89):
            rs, rp = conductor(th, n, k)
            print(f"conductor {name} n={n} k={k} theta={th}: Rs={rs:.12f} Rp={rp:.12f} R={(rs+rp)/2:.12f}")
