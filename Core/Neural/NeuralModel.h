// NeuralModel.h: forwarding header, kept for callers of the old name. The neural design model
// (NeuralDesignModel and its options) is declared in Neural/NeuralDesignModel.h; include that.
#pragma once

#include "Neural/NeuralDesignModel.h"
