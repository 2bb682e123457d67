// The height field generators of include/gonio/measure/heightfield.h.
#include "gonio/measure/heightfield.h"
