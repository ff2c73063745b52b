/* The byte_order attribute of the .vtu files vorocrust writes: binary
 * arrays are written in the machine's own order. */
#ifndef VC_IO_VTU_BYTE_ORDER_H
#define VC_IO_VTU_BYTE_ORDER_H

#if defined(__BYTE_ORDER__) && defined(__ORDER_BIG_ENDIAN__) && \
    __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define VTU_BYTE_ORDER "BigEndian"
#else
#define VTU_BYTE_ORDER "LittleEndian"
#endif

#endif
