#version 450
#include "sky_map.glsl"
