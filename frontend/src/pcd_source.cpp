#include "planemap/frontend/pcd_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <pcl/io/pcd_io.h>

#include "planemap/core/error.h"

namespace planemap {

namespace {

// Bytes one point may take (the sum of SIZE x COUNT over its fields): the PCD files planemap reads
// hold a few numbers a point; PCL's header reader allocates width x height x this before it reads
// a point, so a header claiming more is refused first (fuzz_pcd: SIZE 44444444444444444444444444
// asked for 206 GB).
constexpr long long kMaxPointBytes = 1024;

// PCL's header reader trusts what it reads: it matches keys by prefix ("SIZEx" is SIZE), takes
// the point's fields from whichever of FIELDS, SIZE, TYPE and COUNT came last, allocates POINTS
// (or WIDTH x HEIGHT) x the point's bytes before it reads a point, and parses numbers from a
// stream that splits words where its own tokenizer does not. fuzz_pcd found allocations of
// 85-206 GB, heap corruption and buffer overflows from headers it accepted. So the header is
// checked here first against the PCD format (v0.7) as written: the keys in the format's order
// (VERSION, FIELDS, SIZE, TYPE, COUNT, WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA; VERSION, COUNT
// and VIEWPOINT may be left out), each once, each line printable ASCII words parted by spaces or
// tabs, SIZE, TYPE and COUNT one word per field, each SIZE 1, 2, 4 or 8 as its TYPE has it, a
// point at most kMaxPointBytes, WIDTH, HEIGHT and POINTS the camera's (an organized cloud), the
// fields planemap takes one 4-byte value each, and DATA ascii, binary or binary_compressed.
// Comment lines ('#') and empty lines may stand anywhere before DATA, as the format allows.
struct PcdHeader {
  std::vector<std::string> fields;
  std::vector<long long> sizes, counts;  // counts empty when the header has no COUNT
  std::string kind;                      // DATA's: ascii, binary or binary_compressed
  int data_line = 0;                     // DATA's line number
  long long point_bytes = 0;             // the sum of SIZE x COUNT
};

// Reads `in` up to and past its DATA line; throws InputError naming the file and line.
PcdHeader ReadPcdHeader(std::ifstream& in, const std::string& file, const CameraIntrinsics& camera) {
  static const std::vector<std::string> kKeys = {"VERSION", "FIELDS", "SIZE",      "TYPE",   "COUNT",
                                                 "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  PcdHeader header;
  std::vector<long long>& sizes = header.sizes;
  std::vector<long long>& counts = header.counts;
  std::vector<std::string>& fields = header.fields;
  const long long expected_points = static_cast<long long>(camera.width) * camera.height;
  int last_key = -1;  // index in kKeys of the last key read
  std::string line;
  int number = 0;
  auto fail = [&](const std::string& what) { ThrowInputError(file, number, "not a PCD file (" + what + ")"); };
  auto whole_number = [&](const std::string& key, const std::string& word) {
    const bool digits = !word.empty() && word.size() <= 18 &&
                        std::all_of(word.begin(), word.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits) fail(key + " '" + word + "' is no number");
    return std::stoll(word);
  };
  bool data = false;
  while (!data && in.tellg() < (1 << 20) && std::getline(in, line)) {
    ++number;
    // PCL skips an empty line but ends its header at one of white space only (a lone '\r' too).
    if (!line.empty() && line.find_first_not_of(" \t\r\v\f") == std::string::npos) {
      fail("a header line of white space only");
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;  // empty or a comment
    for (const char c : line) {
      if (c != '\t' && (c < 0x20 || c > 0x7e)) {
        char code[8];
        std::snprintf(code, sizeof(code), "0x%02x", static_cast<unsigned>(static_cast<unsigned char>(c)));
        fail(std::string("a header line holds the byte ") + code);
      }
    }
    // Only spaces and tabs are left to part the words (every other control byte was refused).
    std::vector<std::string> words;
    std::istringstream stream(line);
    for (std::string word; stream >> word;) words.push_back(word);
    std::string key = words[0] == "COLUMNS" ? "FIELDS" : words[0];
    const auto found = std::find(kKeys.begin(), kKeys.end(), key);
    if (found == kKeys.end()) fail("'" + words[0] + "' is no header key");
    const int index = static_cast<int>(found - kKeys.begin());
    if (index <= last_key) {
      fail(key + " " + (index == last_key ? "given twice" : "after " + kKeys[last_key]) +
           "; the header's keys come once each, in the order " +
           "VERSION FIELDS SIZE TYPE COUNT WIDTH HEIGHT VIEWPOINT POINTS DATA");
    }
    for (int k = last_key + 1; k < index; ++k) {
      if (kKeys[k] != "VERSION" && kKeys[k] != "COUNT" && kKeys[k] != "VIEWPOINT") fail("no " + kKeys[k] + " before " + key);
    }
    last_key = index;
    const std::vector<std::string> values(words.begin() + 1, words.end());
    const std::size_t per_field = fields.size();
    auto expect_words = [&](std::size_t n) {
      if (values.size() != n) {
        fail(key + " has " + std::to_string(values.size()) + " value(s), " + std::to_string(n) + " expected" +
             (key == "SIZE" || key == "TYPE" || key == "COUNT" ? " (one for each field)" : ""));
      }
    };
    if (key == "VERSION") {
      expect_words(1);
    } else if (key == "FIELDS") {
      if (values.empty()) fail("FIELDS names no field");
      fields = values;
    } else if (key == "SIZE") {
      expect_words(per_field);
      for (const std::string& word : values) {
        const long long value = whole_number(key, word);
        if (value != 1 && value != 2 && value != 4 && value != 8) fail("SIZE " + word + " is no field size: 1, 2, 4 or 8");
        sizes.push_back(value);
      }
    } else if (key == "TYPE") {
      expect_words(per_field);
      for (std::size_t k = 0; k < values.size(); ++k) {
        const std::string& t = values[k];
        // TYPE and SIZE agree as the format has them (F: 4 or 8 bytes; I and U: 1, 2, 4 or 8): PCL
        // writes a value of the type's width into the field's SIZE bytes, past the point's end for
        // a 2-byte F (a heap corruption fuzz_pcd found).
        if (t != "F" && t != "I" && t != "U") fail("TYPE '" + t + "' is none of F, I, U");
        if (t == "F" && sizes[k] != 4 && sizes[k] != 8) {
          fail("field " + std::to_string(k + 1) + " has TYPE F and SIZE " + std::to_string(sizes[k]));
        }
      }
    } else if (key == "COUNT") {
      expect_words(per_field);
      for (const std::string& word : values) {
        const long long value = whole_number(key, word);
        if (value < 1 || value > kMaxPointBytes) fail("COUNT " + word);
        counts.push_back(value);
      }
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      expect_words(1);
      const long long value = whole_number(key, values[0]);
      const long long want = key == "WIDTH" ? camera.width : key == "HEIGHT" ? camera.height : expected_points;
      if (value != want) {
        ThrowInputError(file, number, key + " " + values[0] + " but the camera's is " + std::to_string(want) +
                                          " (an organized cloud of the camera's " + std::to_string(camera.width) + "x" +
                                          std::to_string(camera.height) + " is needed)");
      }
    } else if (key == "VIEWPOINT") {
      expect_words(7);
      for (const std::string& word : values) {
        std::size_t used = 0;
        double value = 0;
        try {
          value = std::stod(word, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != word.size() || !std::isfinite(value)) fail("VIEWPOINT '" + word + "' is no number");
      }
    } else if (key == "DATA") {
      expect_words(1);
      if (values[0] != "ascii" && values[0] != "binary" && values[0] != "binary_compressed") {
        fail("DATA '" + values[0] + "' is none of ascii, binary, binary_compressed");
      }
      data = true;
      header.kind = values[0];
      header.data_line = number;
    }
  }
  if (!data) {
    if (last_key < 0 && number > 0) ThrowInputError(file, 0, "not a PCD file (no header key in it)");
    ThrowInputError(file, 0, "not a PCD file (no DATA line in its first MB)");
  }
  for (const char* name : {"x", "y", "z"}) {
    if (std::find(fields.begin(), fields.end(), name) == fields.end()) {
      ThrowInputError(file, 0, std::string("cloud has no '") + name + "' field");
    }
  }
  // The fields planemap takes (pcl::PointXYZRGBL's) are one 4-byte value each.
  for (std::size_t k = 0; k < fields.size(); ++k) {
    const std::string& f = fields[k];
    if (f != "x" && f != "y" && f != "z" && f != "rgb" && f != "rgba" && f != "label") continue;
    if (sizes[k] != 4 || (k < counts.size() && counts[k] != 1)) {
      ThrowInputError(file, 0, "not a cloud planemap reads (field '" + f + "' is not one 4-byte value: SIZE " +
                                   std::to_string(sizes[k]) + ")");
    }
  }
  long long bytes = 0;
  for (std::size_t k = 0; k < sizes.size(); ++k) bytes += sizes[k] * (k < counts.size() ? counts[k] : 1);
  if (bytes > kMaxPointBytes) {
    ThrowInputError(file, 0, "a point takes " + std::to_string(bytes) + " bytes (SIZE x COUNT), more than the " +
                                 std::to_string(kMaxPointBytes) + " of any cloud planemap reads");
  }
  header.point_bytes = bytes;
  return header;
}

// PCL's header reader goes on past DATA: it skips empty and comment lines and takes any line
// whose first word begins with a key as more header, until one does not (fuzz_pcd: binary data
// beginning "COLUMNS" gave the cloud other fields, and PCL read past its data). So the lines
// after DATA that PCL reads as header are refused here; points' bytes that happen to begin so
// are as rare as they are fatal. `in` stands after the DATA line, and is left there.
void CheckNoHeaderAfterData(std::ifstream& in, const std::string& file, const PcdHeader& header) {
  const std::streampos data_line_end = in.tellg();
  std::string line;
  static const char* const kPclKeys[] = {"VERSION", "FIELDS", "COLUMNS", "SIZE", "TYPE",  "COUNT",
                                         "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};
  for (int after = 1; std::getline(in, line); ++after) {
    if (line.empty()) continue;
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    const auto begin = std::find_if_not(line.begin(), line.end(), space);
    const std::string word(begin, std::find_if(begin, line.end(), space));
    if (!word.empty() && word[0] == '#') continue;
    for (const char* pcl_key : kPclKeys) {
      if (word.rfind(pcl_key, 0) == 0) {
        ThrowInputError(file, header.data_line + after, std::string("not a PCD file (a line after DATA begins with ") + pcl_key +
                                                  ", which PCL's reader takes as more header)");
      }
    }
    break;
  }
  in.clear();
  in.seekg(data_line_end);
}

// The data's length: binary holds the points' bytes; binary_compressed a block of two sizes
// (compressed, then whole) and the compressed bytes, which must lie in the file and whose whole
// size is the points'. ascii lines are read and counted by PCL. PCL's binary reader copied from
// a null map when a compressed block said it held nothing (fuzz_pcd: SEGV in readBodyBinary).
// `in` stands after the DATA line.
void CheckPcdDataLength(std::ifstream& in, const std::string& file, const PcdHeader& header,
                        const CameraIntrinsics& camera) {
  const long long expected_points = static_cast<long long>(camera.width) * camera.height;
  const std::string& kind = header.kind;
  const long long data_start = static_cast<long long>(in.tellg());
  in.seekg(0, std::ios::end);
  const long long file_size = static_cast<long long>(in.tellg());
  const long long need = header.point_bytes * expected_points;
  if (kind == "binary" && file_size - data_start < need) {
    ThrowInputError(file, 0, "cannot read the PCD file's points (truncated or corrupt: its binary data holds " +
                                 std::to_string(file_size - data_start) + " bytes, " + std::to_string(expected_points) +
                                 " points need " + std::to_string(need) + ")");
  }
  if (kind == "binary_compressed") {
    std::uint32_t block[2] = {0, 0};
    in.seekg(data_start);
    if (file_size - data_start < 8 || !in.read(reinterpret_cast<char*>(block), sizeof(block))) {
      ThrowInputError(file, 0, "cannot read the PCD file's points (truncated or corrupt: no compressed block)");
    }
    if (block[1] != need || block[0] == 0 || static_cast<long long>(block[0]) > file_size - data_start - 8) {
      ThrowInputError(file, 0, "cannot read the PCD file's points (truncated or corrupt: its compressed block of " +
                                   std::to_string(block[0]) + " bytes, " + std::to_string(file_size - data_start - 8) +
                                   " in the file, says it holds " + std::to_string(block[1]) + " bytes; " +
                                   std::to_string(expected_points) + " points take " + std::to_string(need) + ")");
    }
  }
}

// The whole file against the format before PCL reads it (see ReadPcdHeader).
void CheckPcdFile(const std::string& file, const CameraIntrinsics& camera) {
  std::ifstream in(file, std::ios::binary);
  const PcdHeader header = ReadPcdHeader(in, file, camera);
  CheckNoHeaderAfterData(in, file, header);
  CheckPcdDataLength(in, file, header, camera);
}

}  // namespace

PcdFrame LoadOrganizedPcd(const std::string& file, const CameraIntrinsics& camera) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) ThrowInputError(file, 0, "no such PCD file");
  CheckPcdFile(file, camera);
  // PCL's header reader first, on its own: its read() of the points went on after a header it
  // could not read and dereferenced null (fuzz_pcd, before the white-space line check). Then
  // read() gives the points as the file lays them out, and they are taken from there field by
  // field with every offset checked against the data PCL read (pcl::fromPCLPointCloud2 trusts
  // the header's offsets and the data's length: fuzz_pcd found heap-buffer-overflows in it).
  pcl::PCDReader reader;
  pcl::PCLPointCloud2 blob;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0, data_type = 0;
  unsigned int data_start = 0;
  int header_status = -1;
  try {
    header_status = reader.readHeader(file, blob, origin, orientation, version, data_type, data_start);
  } catch (const std::exception& e) {
    ThrowInputError(file, 0, std::string("not a PCD file (broken header: ") + e.what() + ")");
  }
  if (header_status != 0) ThrowInputError(file, 0, "not a PCD file (PCL's reader cannot read its header)");
  int read_status = -1;
  try {
    read_status = reader.read(file, blob);
  } catch (const std::exception& e) {
    ThrowInputError(file, 0, std::string("cannot read the PCD file's points (") + e.what() + ")");
  }
  const std::size_t points = static_cast<std::size_t>(camera.width) * camera.height;
  if (read_status != 0 || static_cast<int>(blob.width) != camera.width ||
      static_cast<int>(blob.height) != camera.height || blob.point_step == 0) {
    ThrowInputError(file, 0, "cannot read the PCD file's points (truncated or corrupt)");
  }
  if (blob.data.size() / blob.point_step < points) {
    ThrowInputError(file, 0, "cannot read the PCD file's points (truncated or corrupt: its data holds " +
                                 std::to_string(blob.data.size()) + " bytes, " + std::to_string(points) +
                                 " points of the header's " + std::to_string(blob.point_step) + " bytes need " +
                                 std::to_string(points * blob.point_step) + ")");
  }
  // A field planemap takes: its byte offset in a point, or -1 when the file has none; it is one
  // 4-byte value of one of `types`, inside the point.
  auto offset_of = [&](std::initializer_list<const char*> names, std::initializer_list<std::uint8_t> types) -> long {
    for (const pcl::PCLPointField& f : blob.fields) {
      if (std::none_of(names.begin(), names.end(), [&](const char* name) { return f.name == name; })) continue;
      if (f.count != 1 || f.offset + 4u > blob.point_step ||
          std::find(types.begin(), types.end(), f.datatype) == types.end()) {
        ThrowInputError(file, 0, "not a cloud planemap reads (field '" + f.name + "' is not one 4-byte " +
                                     (*types.begin() == pcl::PCLPointField::FLOAT32 ? "float" : "integer") +
                                     " inside the point)");
      }
      return static_cast<long>(f.offset);
    }
    return -1;
  };
  using Field = pcl::PCLPointField;
  const long ox = offset_of({"x"}, {Field::FLOAT32});
  const long oy = offset_of({"y"}, {Field::FLOAT32});
  const long oz = offset_of({"z"}, {Field::FLOAT32});
  const long ocolor = offset_of({"rgb", "rgba"}, {Field::FLOAT32, Field::UINT32});
  const long olabel = offset_of({"label"}, {Field::UINT32, Field::INT32});
  for (const auto& [name, offset] : {std::pair{"x", ox}, std::pair{"y", oy}, std::pair{"z", oz}}) {
    if (offset < 0) ThrowInputError(file, 0, std::string("cloud has no '") + name + "' field");
  }
  PcdFrame frame;
  frame.cloud = std::make_shared<Cloud>(camera.width, camera.height);
  frame.cloud->is_dense = false;
  frame.color = ColorImage(camera.width, camera.height);
  frame.labels.assign(points, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::uint8_t* data = blob.data.data();
  auto read4 = [](const std::uint8_t* at, auto value) {
    std::memcpy(&value, at, 4);
    return value;
  };
  for (std::size_t i = 0; i < points; ++i) {
    const std::uint8_t* point = data + i * blob.point_step;
    const float x = read4(point + ox, 0.0f), y = read4(point + oy, 0.0f), z = read4(point + oz, 0.0f);
    auto& q = (*frame.cloud)[i];
    const bool valid = std::isfinite(x) && std::isfinite(y) && std::isfinite(z) && z > 0;
    q.x = valid ? x : nan;
    q.y = valid ? y : nan;
    q.z = valid ? z : nan;
    // PCL's packed colour: 0x00RRGGBB in the field's 4 bytes, whatever its declared type.
    const std::uint32_t rgb = ocolor >= 0 ? read4(point + ocolor, std::uint32_t{0}) : 0u;
    q.r = static_cast<std::uint8_t>((rgb >> 16) & 0xff);
    q.g = static_cast<std::uint8_t>((rgb >> 8) & 0xff);
    q.b = static_cast<std::uint8_t>(rgb & 0xff);
    frame.color.pixels()[i] = {q.r, q.g, q.b};
    if (olabel >= 0) frame.labels[i] = read4(point + olabel, std::uint32_t{0});
  }
  return frame;
}

}  // namespace planemap
