// Ashikhmin-Premoze velvet / cloth distribution ("Distribution-based BRDFs", 2007): an inverted
// Gaussian lobe, D = (1 + 4 exp(-cot^2 / a^2) / sin^4) / (pi (1 + 4 a^2)), sin^2 kept away from 0.
static const float PI = 3.14159265;

float D_Ashikhmin(float NoH, float roughness)
{
    float a2 = roughness * roughness;
    float cos2h = NoH * NoH;
    float sin2h = max(1.0 - cos2h, 0.0078125);
    float sin4h = sin2h * sin2h;
    float cot2 = -cos2h / (a2 * sin2h);
    return 1.0 / (PI * (4.0 * a2 + 1.0) * sin4h) * (4.0 * exp(cot2) + sin4h);
}
