// Works on the OpenVDB grids of a medium (vdbappear::openvdb): the range of its density.
#include <libvdbappear/io/medium.h>

#include <openvdb/tools/Statistics.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 2) return std::fprintf(stderr, "usage: density_range IN.vdb\n"), 2;
  const vdbappear::MediumPtr medium = vdbappear::readMedium(argv[1]);
  const openvdb::math::Extrema range = openvdb::tools::extrema(medium->density->cbeginValueOn());
  std::printf("density %.4f .. %.4f\n", range.min(), range.max());
}
