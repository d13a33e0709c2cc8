// Energy-normalised Blinn-Phong lobe: (n + 8) / (8 pi) NoH^n.
#define PI 3.14159265f

float BlinnPhongNormalized(float NoH, float shininess)
{
    float norm = (shininess + 8.0f) * (1.0f / (8.0f * PI));
    return norm * pow(saturate(NoH), shininess);
}
