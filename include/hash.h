/* hash.h - splitmix64's finaliser, shared by the checkpoint checksums (checkpoint.c) and the
 * segments' breaking-strain draws (material.c). */
#ifndef FABRIC_HASH_H
#define FABRIC_HASH_H

#include <stdint.h>

#define HASH_GOLDEN 0x9e3779b97f4a7c15ULL /* splitmix64's increment, 2^64 / golden ratio */

/* a bijection of 64-bit words in which every input bit moves every output bit */
static inline uint64_t Mix64(uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

#endif
