// Qualitative Oren-Nayar diffuse (Oren and Nayar 1994), written with the angles as older
// engines do: A + B max(0, cos(phi_i - phi_r)) sin(alpha) tan(beta), beta clamped below pi/2.
#define INV_PI 0.31830988618

float OrenNayar(float NoL, float NoV, float cosPhi, float sigma)
{
    float s2 = sigma * sigma;
    float A = 1.0 - 0.5 * s2 / (s2 + 0.33);
    float B = 0.45 * s2 / (s2 + 0.09);
    float thetaL = acos(saturate(NoL));
    float thetaV = acos(saturate(NoV));
    float alpha = max(thetaL, thetaV);
    float beta = min(min(thetaL, thetaV), 1.5);
    return INV_PI * (A + B * max(0.0, cosPhi) * sin(alpha) * tan(beta));
}
