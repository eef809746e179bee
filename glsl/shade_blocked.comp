#version 450
#define TRAIN_BLOCKS
#include "shade.glsl"
