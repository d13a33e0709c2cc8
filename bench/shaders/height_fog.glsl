#version 450
// Exponential height fog: the fog density falls as exp(-falloff * height); the optical depth
// along a ray of length dist and vertical direction rayDirY from a camera at height 0 is
// density * dist * (1 - exp(-falloff * dist * rayDirY)) / (falloff * dist * rayDirY).
float heightFog(float dist, float rayDirY, float density, float falloff)
{
    float x = falloff * dist * rayDirY;
    float factor;
    if (abs(x) > 0.01)
        factor = (1.0 - exp(-x)) / x;
    else
        factor = 1.0 - 0.5 * x;  // its series where x is near 0
    float opticalDepth = density * dist * factor;
    return 1.0 - exp(-opticalDepth);
}
