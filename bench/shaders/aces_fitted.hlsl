// Narkowicz's fit of the ACES filmic curve (2015), applied after an exposure.
#define ACES_A 2.51f
#define ACES_B 0.03f
#define ACES_C 2.43f
#define ACES_D 0.59f
#define ACES_E 0.14f

float ACESFilm(float color, float exposure)
{
    float x = color * exposure * 0.6f;  // the fit expects the input pre-scaled by 0.6
    return saturate((x * (ACES_A * x + ACES_B)) / (x * (ACES_C * x + ACES_D) + ACES_E));
}
