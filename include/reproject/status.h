/* reproject's C interface: status codes (included by reproject/reproject.h, whose conventions apply). */
#ifndef REPROJECT_STATUS_H
#define REPROJECT_STATUS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes (C++ StatusCode). */
typedef int32_t reproject_status;
#define REPROJECT_OK 0
#define REPROJECT_NULL_POINTER 1
#define REPROJECT_INVALID_SIZE 2
#define REPROJECT_INVALID_STRIDE 3
#define REPROJECT_SIZE_MISMATCH 4
#define REPROJECT_ALIASING 5
#define REPROJECT_INVALID_DECODER 6
#define REPROJECT_INVALID_MODEL 7
#define REPROJECT_INVALID_OPTION 8
#define REPROJECT_CANCELLED 9 /* options.cancel was requested during the call: outputs unspecified */
#define REPROJECT_OUT_OF_MEMORY 10 /* the allocator (reproject_set_allocator) returned NULL: nothing kept */

#ifdef __cplusplus
}
#endif

#endif /* REPROJECT_STATUS_H */
