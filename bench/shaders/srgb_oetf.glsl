#version 450
// sRGB encoding (IEC 61966-2-1 OETF): linear to display-referred, with the linear toe.
float linearToSrgb(float c)
{
    if (c <= 0.0031308)
        return 12.92 * c;
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}
