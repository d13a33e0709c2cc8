#version 450
// Beckmann normal distribution, m = roughness^2:
// exp((NoH^2 - 1) / (m^2 NoH^2)) / (pi m^2 NoH^4).
const float PI = 3.141592653589793;

float D_Beckmann(float NoH, float roughness)
{
    float m = roughness * roughness;
    float m2 = m * m;
    float c2 = max(NoH * NoH, 1e-4);
    return exp((c2 - 1.0) / (m2 * c2)) / (PI * m2 * c2 * c2);
}
