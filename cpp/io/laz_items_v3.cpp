#include "io/laz_items.h"
#include "io/laz_reader.h"
namespace pointnpr::laz {
std::unique_ptr<ChunkDecoder> make_layered_decoder(const LaszipVlr&, size_t) {
  throw FormatError("layered LAZ (point formats 6-10) is not supported yet", -1);
}
}
