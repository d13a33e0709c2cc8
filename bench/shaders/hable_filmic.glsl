#version 450
// Hable's filmic curve from Uncharted 2 (GDC 2010), normalised by its value at the white point.
#define SHOULDER_STRENGTH 0.15
#define LINEAR_STRENGTH 0.50
#define LINEAR_ANGLE 0.10
#define TOE_STRENGTH 0.20
#define TOE_NUMERATOR 0.02
#define TOE_DENOMINATOR 0.30
#define LINEAR_WHITE 11.2
#define EXPOSURE_BIAS 2.0

float hableCurve(float x)
{
    float A = SHOULDER_STRENGTH, B = LINEAR_STRENGTH, C = LINEAR_ANGLE;
    float D = TOE_STRENGTH, E = TOE_NUMERATOR, F = TOE_DENOMINATOR;
    return ((x * (A * x + C * B) + D * E) / (x * (A * x + B) + D * F)) - E / F;
}

float hableFilmic(float color)
{
    float curr = hableCurve(EXPOSURE_BIAS * color);
    float whiteScale = 1.0 / hableCurve(LINEAR_WHITE);
    return curr * whiteScale;
}
