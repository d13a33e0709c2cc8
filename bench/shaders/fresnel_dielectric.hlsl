// Exact unpolarised Fresnel reflectance of a dielectric interface, from the cosine of the
// incident angle and the relative index of refraction eta (Walter et al. 2007, eq. 22).
float FresnelDielectric(float cosI, float eta)
{
    float c = abs(cosI);
    float g2 = eta * eta - 1.0 + c * c;
    if (g2 < 0.0)
        return 1.0;  // total internal reflection
    float g = sqrt(g2);
    float A = (g - c) / (g + c);
    float B = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * A * A * (1.0 + B * B);
}
