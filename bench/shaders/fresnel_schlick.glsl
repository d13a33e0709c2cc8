#version 450
// Schlick's Fresnel approximation with the specular colour at normal incidence f0.
float F_Schlick(const float VoH, const float f0)
{
    return f0 + (1.0 - f0) * pow(1.0 - VoH, 5.0);
}
