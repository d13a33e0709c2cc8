"""Independent numpy implementations of the functions of bench/shaders/.

Each is written from the published formula (the paper's or the standard's notation, often a
different but equal algebraic form: angles and Snell's law for the exact Fresnel, Smith's Lambda
for the height-correlated visibility, expm1 for the fog's optical depth), not translated from the
shader, and evaluated in float64 over numpy arrays. The guards a shader's code has on purpose
(a clamped sin^2, a clamped angle, a series near 0) are part of the function and are repeated
here; guards that only keep a division finite outside the benchmark's domain are not.

REFS maps a name (functions.toml's `numpy`) to a callable taking the inputs as keyword
arguments, named as the shader's parameters.
"""

import math

import numpy as np

PI = math.pi


def _clip01(x):
    return np.clip(x, 0.0, 1.0)


# --- BRDF lobes and visibility ---------------------------------------------------------------

def burley_diffuse(NoV, NoL, LoH, roughness):
    # Burley 2012, "Physically-Based Shading at Disney", eq. 3 (without the base colour):
    # f_d = 1/pi (1 + (F_D90 - 1)(1 - cos l)^5)(1 + (F_D90 - 1)(1 - cos v)^5),
    # F_D90 = 1/2 + 2 roughness cos^2(theta_d).
    fd90 = 0.5 + 2.0 * roughness * np.square(LoH)
    return (1.0 + (fd90 - 1.0) * (1.0 - NoL) ** 5) * (1.0 + (fd90 - 1.0) * (1.0 - NoV) ** 5) / PI


def fresnel_dielectric(cosI, eta):
    # Snell's law and the Fresnel equations for s and p polarisation, averaged.
    cos_i = np.abs(cosI)
    sin_t2 = (1.0 - cos_i ** 2) / eta ** 2
    cos_t = np.sqrt(1.0 - sin_t2)  # eta > 1: no total internal reflection
    r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (r_s ** 2 + r_p ** 2)


def fresnel_schlick(VoH, f0):
    # Schlick 1994: F = F0 + (1 - F0)(1 - cos)^5.
    return f0 + (1.0 - f0) * np.power(1.0 - VoH, 5)


def ggx_d(NoH, roughness):
    # Walter et al. 2007, eq. 33, in cos: D = alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2).
    alpha2 = np.maximum(roughness ** 2, 1e-4) ** 2
    return alpha2 / (PI * (np.square(NoH) * (alpha2 - 1.0) + 1.0) ** 2)


def beckmann_d(NoH, roughness):
    # D = exp(-tan^2 / m^2) / (pi m^2 cos^4), m = roughness^2; cos^2 kept >= 1e-4 as the shader
    # keeps it (below that D is exp(-1e4 / m^2), zero in float64).
    m2 = roughness ** 4
    c2 = np.maximum(NoH ** 2, 1e-4)
    tan2 = (1.0 - c2) / c2
    return np.exp(-tan2 / m2) / (PI * m2 * c2 ** 2)


def smith_ggx_correlated(NoV, NoL, roughness):
    # Heitz 2014: G2 = 1 / (1 + Lambda(v) + Lambda(l)),
    # Lambda = (sqrt(1 + alpha^2 tan^2) - 1) / 2; V = G2 / (4 NoV NoL).
    alpha2 = roughness ** 4

    def lam(c):
        tan2 = (1.0 - c ** 2) / c ** 2
        return 0.5 * (np.sqrt(1.0 + alpha2 * tan2) - 1.0)

    g2 = 1.0 / (1.0 + lam(NoV) + lam(NoL))
    return g2 / (4.0 * NoV * NoL)


def smith_schlick(NoV, NoL, Roughness):
    # Schlick's G1 = n.v / (n.v (1 - k) + k), k = (roughness + 1)^2 / 8 (Karis 2013);
    # V = G1(v) G1(l) / (4 n.v n.l), the cosines cancelled.
    k = (Roughness + 1.0) ** 2 / 8.0

    def inv_g1_over_cos(c):
        return c + k * (1.0 - c)

    return 1.0 / (4.0 * inv_g1_over_cos(NoV) * inv_g1_over_cos(NoL))


def charlie_d(NoH, roughness):
    # Estevez and Kulla 2017: D = (2 + 1/r) sin(theta)^(1/r) / (2 pi), r = roughness^2 kept
    # >= 1/128 (the shader's clamp).
    r = np.maximum(roughness ** 2, 1.0 / 128.0)
    sin_h = np.sqrt(np.maximum(1.0 - NoH ** 2, 0.0))
    return (2.0 + 1.0 / r) * sin_h ** (1.0 / r) / (2.0 * PI)


def ashikhmin_d(NoH, roughness):
    # Ashikhmin and Premoze 2007: D = (1 + 4 exp(-cot^2 / a^2) / sin^4) / (pi (1 + 4 a^2)),
    # a = roughness, sin^2 kept >= 1/128 (the shader's clamp).
    a2 = roughness ** 2
    sin2 = np.maximum(1.0 - NoH ** 2, 1.0 / 128.0)
    cot2 = NoH ** 2 / sin2
    return (1.0 + 4.0 * np.exp(-cot2 / a2) / sin2 ** 2) / (PI * (1.0 + 4.0 * a2))


def neubelt_v(NoV, NoL):
    # Neubelt and Pettineo 2013: V = 1 / (4 (n.l + n.v - n.l n.v)), at most 1.
    with np.errstate(divide="ignore"):
        v = 0.25 / (NoL + NoV - NoL * NoV)
    return np.minimum(v, 1.0)


def kelemen_v(LoH):
    # Kelemen and Szirmay-Kalos 2001: V = 1 / (4 (l.h)^2).
    return 1.0 / (4.0 * LoH ** 2)


def blinn_phong(NoH, shininess):
    # Normalised Blinn-Phong: (n + 8) / (8 pi) cos^n.
    return (shininess + 8.0) / (8.0 * PI) * np.power(np.clip(NoH, 0.0, 1.0), shininess)


def oren_nayar(NoL, NoV, cosPhi, sigma):
    # Oren and Nayar 1994, the qualitative model: (A + B max(0, cos phi) sin(alpha) tan(beta)) / pi,
    # alpha = max(theta_l, theta_v), beta = min(theta_l, theta_v) clamped to 1.5 rad. Here sin and
    # tan from the cosines: the larger angle has the smaller cosine.
    s2 = sigma ** 2
    a = 1.0 - 0.5 * s2 / (s2 + 0.33)
    b = 0.45 * s2 / (s2 + 0.09)
    c_alpha = np.minimum(NoL, NoV)
    c_beta = np.maximum(np.maximum(NoL, NoV), math.cos(1.5))
    sin_alpha = np.sqrt(1.0 - c_alpha ** 2)
    tan_beta = np.sqrt(1.0 - c_beta ** 2) / c_beta
    return (a + b * np.maximum(cosPhi, 0.0) * sin_alpha * tan_beta) / PI


# --- phase functions --------------------------------------------------------------------------

def henyey_greenstein(cosTheta, g):
    # Henyey and Greenstein 1941: (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^(3/2)).
    return (1.0 - g ** 2) / (4.0 * PI * (1.0 + g ** 2 - 2.0 * g * cosTheta) ** 1.5)


def schlick_phase(cosTheta, g):
    # Blasi, Le Saec and Schlick 1993: (1 - k^2) / (4 pi (1 - k mu)^2), k = 1.55 g - 0.55 g^3.
    k = 1.55 * g - 0.55 * g ** 3
    return (1.0 - k ** 2) / (4.0 * PI * (1.0 - k * cosTheta) ** 2)


def cornette_shanks(cosTheta, g):
    # Cornette and Shanks 1992, eq. 8:
    # 3/(8 pi) (1 - g^2)(1 + mu^2) / ((2 + g^2)(1 + g^2 - 2 g mu)^(3/2)).
    return (3.0 / (8.0 * PI) * (1.0 - g ** 2) * (1.0 + cosTheta ** 2)
            / ((2.0 + g ** 2) * (1.0 + g ** 2 - 2.0 * g * cosTheta) ** 1.5))


def rayleigh(mu):
    return 3.0 * (1.0 + mu ** 2) / (16.0 * PI)


# --- tonemappers and transfer functions --------------------------------------------------------

def reinhard_extended(L, whitePoint):
    # Reinhard et al. 2002, eq. 4.
    return L * (1.0 + L / whitePoint ** 2) / (1.0 + L)


def aces_narkowicz(color, exposure):
    # Narkowicz 2015: (x (2.51 x + 0.03)) / (x (2.43 x + 0.59) + 0.14), x = 0.6 exposure color,
    # clamped to [0, 1].
    x = 0.6 * exposure * color
    return _clip01((2.51 * x ** 2 + 0.03 * x) / (2.43 * x ** 2 + 0.59 * x + 0.14))


def hable_filmic(color):
    # Hable 2010 (Uncharted 2): f(x) = ((x(Ax + CB) + DE) / (x(Ax + B) + DF)) - E/F with
    # A..F = 0.15, 0.5, 0.1, 0.2, 0.02, 0.3; f(2 color) / f(11.2).
    A, B, C, D, E, F = 0.15, 0.50, 0.10, 0.20, 0.02, 0.30

    def f(x):
        return (A * x * x + C * B * x + D * E) / (A * x * x + B * x + D * F) - E / F

    return f(2.0 * color) / f(11.2)


def srgb_oetf(c):
    # IEC 61966-2-1.
    return np.where(c <= 0.0031308, 12.92 * c,
                    1.055 * np.power(np.maximum(c, 0.0031308), 1.0 / 2.4) - 0.055)


def srgb_eotf(c):
    return np.where(c <= 0.04045, c / 12.92, np.power((np.maximum(c, 0.04045) + 0.055) / 1.055, 2.4))


def pq_eotf(N):
    # SMPTE ST 2084, normalised to 10000 cd/m^2.
    m1 = 2610.0 / 16384.0
    m2 = 2523.0 / 4096.0 * 128.0
    c1 = 3424.0 / 4096.0
    c2 = 2413.0 / 4096.0 * 32.0
    c3 = 2392.0 / 4096.0 * 32.0
    e = np.power(N, 1.0 / m2)
    return np.power(np.maximum(e - c1, 0.0) / (c2 - c3 * e), 1.0 / m1)


def toon_ramp(NoL):
    # Half-Lambert (NoL / 2 + 1/2) quantised down to quarters, then lerped from 0.15 to 1.
    steps = np.floor(2.0 * (NoL + 1.0)) / 4.0
    return 0.15 + 0.85 * steps


# --- lights, occlusion, fog -------------------------------------------------------------------

def ue4_falloff(dist, radius):
    # Karis 2013, eq. 9: saturate(1 - (d / r)^4)^2 / (d^2 + 1).
    return _clip01(1.0 - (dist / radius) ** 4) ** 2 / (dist ** 2 + 1.0)


def spot_cone(cosAngle, cosOuter, penumbra):
    # Hermite smoothstep from the outer cone's cosine to the inner one's.
    t = _clip01((cosAngle - cosOuter) / penumbra)
    return t * t * (3.0 - 2.0 * t)


def specular_occlusion(NdotV, AO, roughness):
    # Lagarde and de Rousiers 2014, listing 26.
    return _clip01((NdotV + AO) ** (2.0 ** (-16.0 * roughness - 1.0)) - 1.0 + AO)


def height_fog(dist, rayDirY, density, falloff):
    # Optical depth of density * exp(-falloff * h) along h = s * rayDirY, s from 0 to dist:
    # density * dist * (1 - exp(-x)) / x, x = falloff * dist * rayDirY; where |x| <= 0.01 the
    # shader takes the series' first two terms, 1 - x / 2, and so does this.
    x = falloff * dist * rayDirY
    with np.errstate(divide="ignore", invalid="ignore"):
        exact = -np.expm1(-x) / x
    factor = np.where(np.abs(x) > 0.01, exact, 1.0 - 0.5 * x)
    return -np.expm1(-density * dist * factor)


REFS = {
    "burley_diffuse": burley_diffuse,
    "henyey_greenstein": henyey_greenstein,
    "schlick_phase": schlick_phase,
    "cornette_shanks": cornette_shanks,
    "rayleigh": rayleigh,
    "fresnel_dielectric": fresnel_dielectric,
    "fresnel_schlick": fresnel_schlick,
    "ggx_d": ggx_d,
    "beckmann_d": beckmann_d,
    "smith_ggx_correlated": smith_ggx_correlated,
    "smith_schlick": smith_schlick,
    "charlie_d": charlie_d,
    "ashikhmin_d": ashikhmin_d,
    "neubelt_v": neubelt_v,
    "oren_nayar": oren_nayar,
    "kelemen_v": kelemen_v,
    "blinn_phong": blinn_phong,
    "reinhard_extended": reinhard_extended,
    "aces_narkowicz": aces_narkowicz,
    "hable_filmic": hable_filmic,
    "srgb_oetf": srgb_oetf,
    "srgb_eotf": srgb_eotf,
    "pq_eotf": pq_eotf,
    "toon_ramp": toon_ramp,
    "ue4_falloff": ue4_falloff,
    "spot_cone": spot_cone,
    "specular_occlusion": specular_occlusion,
    "height_fog": height_fog,
}
