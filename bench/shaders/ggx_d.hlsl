// GGX / Trowbridge-Reitz normal distribution, alpha = perceptual roughness squared.
#define PI 3.14159265359f
#define MIN_ALPHA 1e-4f

float D_GGX(float NoH, float roughness)
{
    float alpha = max(roughness * roughness, MIN_ALPHA);
    float a2 = alpha * alpha;
    float d = (NoH * a2 - NoH) * NoH + 1.0f;
    return a2 / (PI * d * d);
}
