#include "common/image_io.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "common/error.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mrr {
namespace {

// Values that exercise every float bit pattern class we care about (not halfs: 1/3 and
// 1e-7 are not representable as half, so a HALF write would fail the bit-exact check).
ImageF patternImage(int w, int h, int c) {
  ImageF image(w, h, c);
  for (size_t i = 0; i < image.data.size(); ++i)
    image.data[i] = static_cast<float>(i) / 3.0f + 1e-7f * static_cast<float>(i % 5) - 2.0f;
  return image;
}

bool bitEqual(const ImageF& a, const ImageF& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

std::vector<std::string> listDir(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const MrrError& e) {
    return e.what();
  }
  return "";
}

TEST(ImageIo, ExrOneChannelRoundTripIsBitExact) {
  const std::string dir = test::scratchDir();
  const std::string path = dir + "/depth.exr";
  const ImageF image = patternImage(7, 5, 1);
  writeImage(path, image, {"Z"});
  const std::vector<ExrPart> parts = readParts(path);
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0].channelNames, std::vector<std::string>{"Z"});
  EXPECT_TRUE(bitEqual(parts[0].image, image));
  EXPECT_TRUE(bitEqual(readImage(path), image));
}

TEST(ImageIo, ExrFourChannelsKeepNamesAndValues) {
  const std::string dir = test::scratchDir();
  const std::string path = dir + "/gbuffer.exr";
  const ImageF image = patternImage(7, 5, 4);
  const std::vector<std::string> names = {"normal.x", "normal.y", "normal.z", "depth"};
  writeImage(path, image, names);
  const std::vector<ExrPart> parts = readParts(path);
  ASSERT_EQ(parts.size(), 1u);
  const ExrPart& part = parts[0];
  ASSERT_EQ(part.image.width, 7);
  ASSERT_EQ(part.image.height, 5);
  ASSERT_EQ(part.image.channels, 4);
  // OIIO may reorder extra channels: match by name, compare bit-exactly.
  for (size_t c = 0; c < names.size(); ++c) {
    auto it = std::find(part.channelNames.begin(), part.channelNames.end(), names[c]);
    ASSERT_NE(it, part.channelNames.end()) << names[c];
    const int fileChannel = static_cast<int>(it - part.channelNames.begin());
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 7; ++x)
        EXPECT_EQ(std::memcmp(&part.image.at(x, y, fileChannel),
                              &image.at(x, y, static_cast<int>(c)), sizeof(float)),
                  0);
  }
}

TEST(ImageIo, ExrDefaultChannelNames) {
  const std::string dir = test::scratchDir();
  writeImage(dir + "/rgba.exr", patternImage(3, 2, 4));
  writeImage(dir + "/y.exr", patternImage(3, 2, 1));
  writeImage(dir + "/five.exr", patternImage(3, 2, 5));
  EXPECT_EQ(readParts(dir + "/rgba.exr")[0].channelNames,
            (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(readParts(dir + "/y.exr")[0].channelNames, std::vector<std::string>{"Y"});
  const ExrPart five = readParts(dir + "/five.exr")[0];
  ASSERT_EQ(five.channelNames.size(), 5u);
  EXPECT_TRUE(bitEqual(five.image, patternImage(3, 2, 5)));  // c0..c4 keep their order
}

TEST(ImageIo, ExrWrongChannelNameCountThrows) {
  const std::string dir = test::scratchDir();
  EXPECT_THROW(writeImage(dir + "/bad.exr", patternImage(3, 2, 3), {"R", "G"}), MrrError);
  EXPECT_TRUE(listDir(dir).empty());
}

TEST(ImageIo, MultiPartExrRoundTrip) {
  const std::string dir = test::scratchDir();
  const std::string path = dir + "/levels.exr";
  std::vector<ExrPart> parts = {
      {"level0", patternImage(9, 7, 1), {"ao"}},
      {"level1", patternImage(5, 4, 3), {"R", "G", "B"}},
      {"level2", patternImage(3, 2, 2), {"u", "v"}},
  };
  writeMultiPartExr(path, parts, 9, 7);
  const std::vector<ExrPart> back = readParts(path);
  ASSERT_EQ(back.size(), parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    EXPECT_EQ(back[i].name, parts[i].name);
    EXPECT_EQ(back[i].channelNames, parts[i].channelNames);
    EXPECT_TRUE(bitEqual(back[i].image, parts[i].image)) << parts[i].name;
  }
  EXPECT_TRUE(bitEqual(readImage(path), parts[0].image));
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"levels.exr"});
}

TEST(ImageIo, MultiPartExrRejectsDuplicateNames) {
  const std::string dir = test::scratchDir();
  std::vector<ExrPart> parts = {{"a", patternImage(2, 2, 1), {}}, {"a", patternImage(2, 2, 1), {}}};
  EXPECT_THROW(writeMultiPartExr(dir + "/dup.exr", parts, 2, 2), MrrError);
  EXPECT_TRUE(listDir(dir).empty());
}

TEST(ImageIo, PngClampsAndReadsBackBytes) {
  const std::string dir = test::scratchDir();
  const std::string path = dir + "/preview.png";
  ImageF image(4, 1, 3);
  const float values[4] = {0.0f, 1.0f, -0.5f, 2.0f};
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) image.at(x, 0, c) = values[x];
  writeImage(path, image);
  const ImageF back = readImage(path);
  ASSERT_EQ(back.width, 4);
  ASSERT_EQ(back.height, 1);
  ASSERT_EQ(back.channels, 3);
  const float expected[4] = {0.0f, 1.0f, 0.0f, 1.0f};  // OIIO reads 8-bit as byte/255
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(back.at(x, 0, c), expected[x]) << x;
}

TEST(ImageIo, PngRoundsAndEncodesSrgb) {
  const std::string dir = test::scratchDir();
  ImageF grey(3, 1, 1);
  grey.at(0, 0) = 0.5f;
  grey.at(1, 0) = 0.002f;  // on the linear segment of the sRGB curve
  grey.at(2, 0) = 1.0f;
  writeImage(dir + "/linear.png", grey);
  writeImage(dir + "/srgb.png", grey, {}, true);
  const ImageF linear = readImage(dir + "/linear.png");
  const ImageF srgb = readImage(dir + "/srgb.png");
  ASSERT_EQ(linear.channels, 1);
  EXPECT_FLOAT_EQ(linear.at(0, 0) * 255.0f, 128.0f);  // 127.5 rounds to nearest (up)
  EXPECT_FLOAT_EQ(linear.at(1, 0) * 255.0f, 1.0f);    // 0.51 -> 1
  EXPECT_FLOAT_EQ(srgb.at(0, 0) * 255.0f, 188.0f);    // 1.055·0.5^(1/2.4)−0.055 = 0.7354
  EXPECT_FLOAT_EQ(srgb.at(1, 0) * 255.0f, 7.0f);      // 12.92·0.002·255 = 6.59
  EXPECT_FLOAT_EQ(srgb.at(2, 0), 1.0f);
}

TEST(ImageIo, PngFourChannelsIsOpaqueRgb) {
  const std::string dir = test::scratchDir();
  ImageF image(2, 2, 4, 1.0f);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) image.at(x, y, 3) = 0.25f;  // would darken if premultiplied
  writeImage(dir + "/rgba.png", image);
  const ImageF back = readImage(dir + "/rgba.png");
  ASSERT_EQ(back.channels, 3);
  for (float v : back.data) EXPECT_EQ(v, 1.0f);
}

TEST(ImageIo, PngTwoChannelsGoToRedAndGreen) {
  const std::string dir = test::scratchDir();
  ImageF image(1, 1, 2);
  image.at(0, 0, 0) = 1.0f;
  image.at(0, 0, 1) = 0.0f;
  writeImage(dir + "/rg.png", image);
  const ImageF back = readImage(dir + "/rg.png");
  ASSERT_EQ(back.channels, 3);
  EXPECT_EQ(back.at(0, 0, 0), 1.0f);
  EXPECT_EQ(back.at(0, 0, 1), 0.0f);
  EXPECT_EQ(back.at(0, 0, 2), 0.0f);
  EXPECT_THROW(writeImage(dir + "/five.png", ImageF(1, 1, 5)), MrrError);
}

TEST(ImageIo, MissingDirectoryThrowsAndLeavesNothing) {
  const std::string dir = test::scratchDir();
  const std::string path = dir + "/missing/out.exr";
  const std::string message = errorOf([&] { writeImage(path, patternImage(2, 2, 1)); });
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  EXPECT_TRUE(listDir(dir).empty());
  EXPECT_THROW(writeTextFile(dir + "/missing/report.json", "{}"), MrrError);
  EXPECT_THROW(writeMultiPartExr(path, {{"a", patternImage(2, 2, 1), {}}}, 2, 2), MrrError);
  EXPECT_TRUE(listDir(dir).empty());
}

TEST(ImageIo, DirectoryAsPathThrows) {
  const std::string dir = test::scratchDir();
  fs::create_directory(dir + "/taken.exr");
  const std::string message =
      errorOf([&] { writeImage(dir + "/taken.exr", patternImage(2, 2, 1)); });
  EXPECT_NE(message.find("is a directory"), std::string::npos) << message;
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"taken.exr"});
  EXPECT_TRUE(fs::is_directory(dir + "/taken.exr"));
}

TEST(ImageIo, NoTemporaryFilesRemainAfterSuccess) {
  const std::string dir = test::scratchDir();
  writeImage(dir + "/a.exr", patternImage(3, 3, 3));
  writeImage(dir + "/b.png", patternImage(3, 3, 3));
  writeMultiPartExr(dir + "/c.exr", {{"p", patternImage(3, 3, 1), {}}}, 3, 3);
  writeTextFile(dir + "/d.json", "{\"ok\": true}\n");
  writeImage(dir + "/a.exr", patternImage(3, 3, 1));  // overwriting replaces in place
  EXPECT_EQ(listDir(dir), (std::vector<std::string>{"a.exr", "b.png", "c.exr", "d.json"}));
  EXPECT_EQ(readImage(dir + "/a.exr").channels, 1);
  std::ifstream text(dir + "/d.json");
  std::string content((std::istreambuf_iterator<char>(text)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "{\"ok\": true}\n");
}

TEST(ImageIo, TemporaryPathKeepsDirectoryAndExtension) {
  const std::string a = temporaryPathFor("/d/out.exr");
  const std::string b = temporaryPathFor("/d/out.exr");
  EXPECT_NE(a, b);
  EXPECT_EQ(fs::path(a).parent_path(), fs::path("/d"));
  EXPECT_EQ(fs::path(a).extension(), ".exr");
  EXPECT_EQ(fs::path(a).filename().string().rfind(".out.exr.tmp-", 0), 0u) << a;
  EXPECT_EQ(fs::path(temporaryPathFor("x.png")).extension(), ".png");
  EXPECT_TRUE(fs::path(temporaryPathFor("x.png")).parent_path().empty());
}

TEST(ImageIo, CheckOutputPathCases) {
  const std::string dir = test::scratchDir();
  EXPECT_NO_THROW(checkOutputPath(dir + "/ok.exr", "--out"));
  EXPECT_NO_THROW(checkOutputPath(dir + "/ok.PNG", "--out"));
  EXPECT_NO_THROW(checkOutputPath(dir + "/report.json", "--report"));

  std::string m = errorOf([&] { checkOutputPath(dir + "/nope/x.exr", "--out"); });
  EXPECT_EQ(m, "--out " + dir + "/nope/x.exr: directory " + dir + "/nope does not exist");
  m = errorOf([&] { checkOutputPath(dir, "--out"); });
  EXPECT_EQ(m, "--out " + dir + ": is a directory");
  m = errorOf([&] { checkOutputPath(dir + "/x.tiff", "--out"); });
  EXPECT_NE(m.find("unsupported extension"), std::string::npos) << m;
  EXPECT_NE(m.find("use .exr or .png"), std::string::npos) << m;
  EXPECT_NE(errorOf([&] { checkOutputPath(dir + "/noext", "--out"); }), "");

  std::ofstream(dir + "/file") << "x";
  m = errorOf([&] { checkOutputPath(dir + "/file/x.exr", "--out"); });
  EXPECT_NE(m.find("not a directory"), std::string::npos) << m;
}

TEST(ImageIo, CheckOutputPathUnwritableDirectory) {
  const std::string dir = test::scratchDir();
  const std::string locked = dir + "/locked";
  fs::create_directory(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::others_read |
                              fs::perms::others_exec | fs::perms::group_read | fs::perms::group_exec);
  const std::string expected = "--out " + locked + "/x.exr: directory " + locked + " is not writable";
  if (::geteuid() != 0) {
    EXPECT_EQ(errorOf([&] { checkOutputPath(locked + "/x.exr", "--out"); }), expected);
  } else {
    // Root writes anywhere: check as `nobody`, in a child that drops its privileges.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      if (::setgid(65534) != 0 || ::setuid(65534) != 0) ::_exit(3);
      ::_exit(errorOf([&] { checkOutputPath(locked + "/x.exr", "--out"); }) == expected ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "as nobody, the error was not \"" << expected << "\" (3: setuid failed)";
  }
  fs::permissions(locked, fs::perms::owner_all);
}

TEST(ImageIo, ReadingMissingOrCorruptFileThrows) {
  const std::string dir = test::scratchDir();
  std::string m = errorOf([&] { readImage(dir + "/absent.exr"); });
  EXPECT_NE(m.find(dir + "/absent.exr"), std::string::npos) << m;
  std::ofstream(dir + "/corrupt.exr") << "this is not an exr file";
  EXPECT_THROW(readParts(dir + "/corrupt.exr"), MrrError);
  std::ofstream(dir + "/corrupt.png") << "\x89PNG garbage";
  EXPECT_THROW(readImage(dir + "/corrupt.png"), MrrError);
}

}  // namespace
}  // namespace mrr
