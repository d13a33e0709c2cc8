#version 450
// Extended Reinhard tonemapper (Reinhard et al. 2002, eq. 4): L (1 + L / Lwhite^2) / (1 + L).
float reinhardExtended(float L, float whitePoint)
{
    float invW2 = 1.0 / (whitePoint * whitePoint);
    return L * (1.0 + L * invW2) / (1.0 + L);
}
