#version 450
// Cel-shading ramp: half-Lambert lighting quantised to bands, softened by a small ambient term.
#define BANDS 4.0
#define AMBIENT 0.15

float toonRamp(float NoL)
{
    float halfLambert = NoL * 0.5 + 0.5;
    float band = floor(halfLambert * BANDS) / BANDS;
    return mix(AMBIENT, 1.0, band);
}
