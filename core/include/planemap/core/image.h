#pragma once
// A minimal row-major image. Core stays free of OpenCV; io/ and sim/ convert at their boundary.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace planemap {

using Rgb8 = std::array<std::uint8_t, 3>;  // red, green, blue

template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, const T& fill = T{})
      : width_(width), height_(height), data_(static_cast<size_t>(width) * height, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return data_.empty(); }
  size_t size() const { return data_.size(); }

  // Pixel at column u, row v.
  T& at(int u, int v) { return data_[static_cast<size_t>(v) * width_ + u]; }
  const T& at(int u, int v) const { return data_[static_cast<size_t>(v) * width_ + u]; }

  T* data() { return data_.data(); }
  const T* data() const { return data_.data(); }
  std::vector<T>& pixels() { return data_; }
  const std::vector<T>& pixels() const { return data_; }

  bool operator==(const Image& other) const {
    return width_ == other.width_ && height_ == other.height_ && data_ == other.data_;
  }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> data_;
};

using DepthImage = Image<float>;          // metres; 0 = no measurement
using ColorImage = Image<Rgb8>;
using LabelImage = Image<std::uint16_t>;  // 0 = no surface

// True for a usable depth value: finite and positive.
inline bool IsValidDepth(float z) { return z > 0.0f && z < 1e30f; }

}  // namespace planemap
