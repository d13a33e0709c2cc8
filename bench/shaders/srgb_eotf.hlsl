// sRGB decoding (EOTF): display-referred to linear.
float SRGBToLinear(float c)
{
    return (c <= 0.04045) ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}
