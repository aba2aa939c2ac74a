/* tiles_kernel_4.h: tiles_kernel.h with the parameters of a 4 x 4 copy
 * (AVX2's vectors of 4 doubles), for the copies that differ only in name
 * and instruction set: tiles.c defines TK and TK_TARGET, then includes
 * this file (tiles_kernel.h undefines them all at its end). */
#define TK_SPECIALISE 1
#define TK_W 4
#define TK_VD v4d
#define TK_VI v4i
#define TK_ANY(m) (_mm256_movemask_pd((__m256d)(m)) != 0)
#define TK_MAX(a, b) ((v4d)_mm256_max_pd((__m256d)(a), (__m256d)(b)))
#define TK_ALL(m) (_mm256_movemask_pd((__m256d)(m)) == 0xf)
#define TK_SQRT(p) (*(p) = (v4d)_mm256_sqrt_pd((__m256d) * (p)))
#include "tiles_kernel.h"
