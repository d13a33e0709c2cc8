#version 450
// "Charlie" sheen distribution (Estevez and Kulla 2017): D = (2 + 1/r) sin^(1/r)(theta_h) / (2 pi).
#define PI 3.14159265359

float D_Charlie(float NoH, float roughness)
{
    float r = max(roughness * roughness, 0.0078125);
    float invR = 1.0 / r;
    float sin2h = max(1.0 - NoH * NoH, 0.0);
    return (2.0 + invR) * pow(sin2h, invR * 0.5) / (2.0 * PI);
}
