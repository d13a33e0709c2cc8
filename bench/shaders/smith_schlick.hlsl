// Separable Smith visibility with Schlick's G1 and k = (roughness + 1)^2 / 8
// (Karis 2013, the remapping for analytic lights), V = G / (4 NoL NoV).
float G1_Schlick(float NoX, float k)
{
    return 1.0 / (NoX * (1.0 - k) + k);
}

float Vis_SmithSchlick(float NoV, float NoL, float Roughness)
{
    float r = Roughness + 1.0;
    float k = (r * r) / 8.0;
    return 0.25 * G1_Schlick(NoV, k) * G1_Schlick(NoL, k);
}
