/* matrix.h: small matrix kernels shared by the maths and colour built-ins. */
#ifndef FL_MATRIX_H
#define FL_MATRIX_H

/* Inverse of the column-major 3x3 matrix [m] into [r], with the exact
 * operation order of inverse() (LANGUAGE.md §5.4): adjugate times 1/det. */
void mat3_inverse(const double m[9], double r[9]);

#endif
