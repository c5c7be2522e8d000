// Image memory (common/pixel_memory.h): images of 64 KiB or more come from one pool
// that keeps freed images' pages for the next image, so a frame's pages are faulted in once per
// process, not once per frame.
#include <gtest/gtest.h>

#include "common/image.h"
#include "common/pixel_memory.h"

namespace mrr {
namespace {

#ifndef MRR_SANITIZED
TEST(PixelMemory, AFreedImageIsReusedNotMappedAgain) {
  { const ImageF warm(1280, 720, 3, 0.0f); }  // the pool's first pages
  const size_t held = pixelPoolBytes();
  EXPECT_GT(held, size_t{1280} * 720 * 3 * 4 - 1);
  for (int frame = 0; frame < 5; ++frame) {
    const ImageF a(1280, 720, 3, 1.0f);
    EXPECT_EQ(a.at(1279, 719, 2), 1.0f);
  }
  EXPECT_EQ(pixelPoolBytes(), held) << "five frames' images of the same size took no new memory";
}

TEST(PixelMemory, SmallImagesStayOnTheHeap) {
  const size_t held = pixelPoolBytes();
  const ImageU8 small(100, 100, 1, 1);  // 10 KB: below kPooledPixelBytes
  EXPECT_EQ(pixelPoolBytes(), held);
}
#endif

}  // namespace
}  // namespace mrr
