"""Our LDR-FLIP (src/image/flip.cpp, bound as shaderfit._shaderfit.ldr_flip) against NVIDIA's
flip-evaluator on procedurally made image pairs: the means agree within 1e-3 and the per-pixel
maps within 2e-3 (measured: about 5e-5). The closed-form pairs here (sphere, banding, waves) are
the ones src/image/flip_test.cpp keeps golden means of, and this test checks those goldens too."""

import numpy as np
import pytest

flip_evaluator = pytest.importorskip(
    "flip_evaluator", reason="skipped: flip-evaluator is not installed (scripts/install-deps)")
_shaderfit = pytest.importorskip("shaderfit._shaderfit")

DEFAULT_PPD = 0.7 * (3840 / 0.7) * (np.pi / 180)

# flip-evaluator's means of the closed-form pairs, as src/image/flip_test.cpp states them.
GOLDEN = {"sphere": 0.0544356, "banding": 0.1560945, "waves": 0.2712007}


def srgb_encode(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def normalize(v):
    v = np.asarray(v, dtype=np.float64)
    return v / np.linalg.norm(v)


# The closed-form pairs: written the same way as in src/image/flip_test.cpp.
def sphere(size, light, shininess):
    """A Blinn-Phong sphere of radius 0.8 over a vertical gradient, lit from `light`."""
    j, i = np.meshgrid(np.arange(size), np.arange(size))
    u = (j + 0.5) / size * 2 - 1
    v = 1 - (i + 0.5) / size * 2
    r2 = u * u + v * v
    inside = r2 < 0.64
    nz = np.sqrt(np.maximum(0.64 - r2, 0.0)) / 0.8
    n = np.stack([u / 0.8, v / 0.8, nz], axis=-1)
    light = normalize(light)
    half = normalize(light + np.array([0.0, 0.0, 1.0]))
    diffuse = np.maximum(n @ light, 0.0)
    specular = np.maximum(n @ half, 0.0) ** shininess
    albedo = np.array([0.8, 0.3, 0.2])
    lit = 0.03 + albedo * diffuse[..., None] + 0.3 * specular[..., None]
    background = (0.2 + 0.1 * v)[..., None] * np.array([0.6, 0.7, 1.0])
    return srgb_encode(np.where(inside[..., None], lit, background)).astype(np.float32)


def banding_pair(w=80, h=48):
    """A colour ramp, and the same ramp quantised to 16 levels."""
    t = np.broadcast_to((np.arange(w) + 0.5) / w, (h, w))
    q = np.floor(t * 16) / 15
    ramp = lambda s: np.stack([s, s * s, 1 - s], axis=-1)
    return ramp(t).astype(np.float32), ramp(q).astype(np.float32)


def waves_pair(w=72, h=56):
    """Coloured sine waves, and the same with a phase shift and dimmer blue."""
    x, y = np.meshgrid(np.arange(w, dtype=np.float64), np.arange(h, dtype=np.float64))

    def waves(phase, blue):
        return np.stack([0.5 + 0.4 * np.sin(0.35 * x + 0.2 * y + phase),
                         0.5 + 0.4 * np.cos(0.27 * y),
                         blue * (0.5 + 0.4 * np.sin(0.19 * (x - y)))], axis=-1)

    return waves(0.0, 1.0).astype(np.float32), waves(0.3, 0.9).astype(np.float32)


def closed_form_pairs():
    return {
        "sphere": (sphere(64, [0.5, 0.6, 0.62], 32.0), sphere(64, [0.55, 0.6, 0.58], 24.0)),
        "banding": banding_pair(),
        "waves": waves_pair(),
    }


def seeded_pairs():
    """Pairs with noise from a seeded generator: renders and the usual kinds of difference."""
    rng = np.random.default_rng(20200807)
    h, w = 70, 90
    noise = rng.random((h, w, 3)).astype(np.float32)
    clean = sphere(96, [0.4, 0.7, 0.6], 40.0)
    # A path-traced look: the same sphere with per-pixel noise in linear light.
    linear = np.where(clean <= 0.04045, clean / 12.92, ((clean + 0.055) / 1.055) ** 2.4)
    noisy = srgb_encode(linear * (1 + 0.15 * rng.standard_normal(linear.shape)))
    x = np.linspace(0, 1, w)[None, :]
    y = np.linspace(0, 1, h)[:, None]
    yellow = np.stack([x + 0 * y, x + 0 * y, 0 * x + 0 * y], axis=-1)
    blue = yellow.copy()
    blue[..., 2] = 0.8 * y
    blob = np.exp(-((x - 0.4) ** 2 + (y - 0.5) ** 2) / 0.05)[..., None] * np.array([0.9, 0.6, 0.3])
    hue = blob[..., [1, 0, 2]]
    return {
        "noise": (noise, np.clip(noise + 0.1 * rng.standard_normal(noise.shape), 0, 1)),
        "shift": (noise, np.roll(noise, 1, axis=1)),
        "noisy_sphere": (clean, noisy.astype(np.float32)),
        "blue_yellow": (yellow.astype(np.float32), blue.astype(np.float32)),
        "hue": (blob.astype(np.float32), hue.astype(np.float32)),
        "identical": (noise, noise),
    }


def compare(reference, test, ppd):
    reference = np.ascontiguousarray(reference, dtype=np.float32)
    test = np.ascontiguousarray(test, dtype=np.float32)
    theirs, their_mean, _ = flip_evaluator.evaluate(reference, test, "LDR", applyMagma=False,
                                                    parameters={"ppd": ppd})
    ours, our_mean = _shaderfit.ldr_flip(reference, test, ppd)
    ours = ours.reshape(reference.shape[:2])
    return their_mean, our_mean, float(np.max(np.abs(ours - theirs[..., 0])))


ALL_PAIRS = {**closed_form_pairs(), **seeded_pairs()}


@pytest.mark.parametrize("ppd", [DEFAULT_PPD, 30.0])
@pytest.mark.parametrize("name", sorted(ALL_PAIRS))
def test_agrees_with_flip_evaluator(name, ppd):
    their_mean, our_mean, max_pixel = compare(*ALL_PAIRS[name], ppd)
    print(f"{name} ppd {ppd:.2f}: flip-evaluator {their_mean:.7f} ours {our_mean:.7f} "
          f"|mean diff| {abs(their_mean - our_mean):.1e} max pixel diff {max_pixel:.1e}")
    assert abs(their_mean - our_mean) < 1e-3
    assert max_pixel < 2e-3


@pytest.mark.parametrize("name", sorted(GOLDEN))
def test_cpp_goldens_are_flip_evaluators(name):
    _, mean, _ = flip_evaluator.evaluate(*closed_form_pairs()[name], "LDR", applyMagma=False,
                                         parameters={"ppd": DEFAULT_PPD})
    assert mean == pytest.approx(GOLDEN[name], abs=2e-6)
