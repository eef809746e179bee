#version 450
#define PHYSICAL_SKY
#include "sky_map.glsl"
