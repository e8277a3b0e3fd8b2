// ddes roscpp: the fixed-width integer types messages use (int8_t ... uint64_t).
#ifndef ROSCPP_TYPES_H
#define ROSCPP_TYPES_H

#include <stdint.h>

#endif  // ROSCPP_TYPES_H
