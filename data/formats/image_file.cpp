#include "data/formats/image_file.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>

#include <sys/stat.h>

#include <jpeglib.h>
#include <jerror.h>  // after jpeglib.h: the message codes
#include <png.h>
#include <zlib.h>

#include <opencv2/imgproc.hpp>

#include "data/formats/atomic_file.h"
#include "data/formats/grey_png.h"
#include "data/input_error.h"
#include "data/media/media_loader.h"

// libpng and libjpeg report errors by longjmp. Each function below that calls setjmp keeps only
// trivially destructible locals (the library's own structs, pointers); images and byte buffers
// are owned by the caller, so a longjmp skips no destructor.

namespace adugs::data {
namespace {

// The ancillary chunks that do not change the pixels adugs reads (the colour-space ones, gAMA,
// cHRM, sRGB, iCCP, do: libpng converts colour to grey through them, as for OpenCV), as 4-letter
// names each ended by a zero byte.
constexpr png_byte kIgnoredPngChunks[] =
    "bKGD\0eXIf\0hIST\0iTXt\0oFFs\0pCAL\0pHYs\0sCAL\0sPLT\0sTER\0tEXt\0tIME\0zTXt";
constexpr int kIgnoredPngChunkCount = static_cast<int>(sizeof kIgnoredPngChunks / 5);
// The largest ICC profile libpng may allocate (real ones are a few kB to a few hundred kB).
constexpr png_alloc_size_t kMaxPngChunkBytes = 8u << 20;

struct ErrorText {
  char text[JMSG_LENGTH_MAX > 256 ? JMSG_LENGTH_MAX : 256] = "";
  void set(const char* message) { std::snprintf(text, sizeof text, "%s", message); }
};

bool isPng(const uint8_t* data, size_t size) { return size >= 8 && png_sig_cmp(data, 0, 8) == 0; }
bool isJpeg(const uint8_t* data, size_t size) {
  return size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
}

// ---- PNG ------------------------------------------------------------------------------------

// Bytes in memory, or an open file. Files are read through stdio, not loaded first: decoding from
// a 300 KB buffer was 1.3x slower than from stdio's small hot one (EuRoC frames, this VM).
struct ImageInput {
  const uint8_t* data = nullptr;
  size_t size = 0;
  size_t pos = 0;
  FILE* file = nullptr;
};

void pngRead(png_structp png, png_bytep out, png_size_t n) {
  auto* in = static_cast<ImageInput*>(png_get_io_ptr(png));
  if (in->file) {
    if (std::fread(out, 1, n, in->file) != n) png_error(png, "the data ends before the image does (truncated)");
    return;
  }
  if (in->size - in->pos < n) png_error(png, "the data ends before the image does (truncated)");
  std::memcpy(out, in->data + in->pos, n);
  in->pos += n;
}

void pngError(png_structp png, png_const_charp message) {
  static_cast<ErrorText*>(png_get_error_ptr(png))->set(message);
  png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}  // e.g. an unknown ancillary chunk: not an error

void setPngByteOrder(png_structp png) {
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  png_set_swap(png);  // PNG stores 16-bit samples big-endian
#else
  (void)png;
#endif
}

// The transforms of cv::imread for IMREAD_GRAYSCALE and IMREAD_UNCHANGED.
bool decodePng(ImageInput& in, ImageRead mode, cv::Mat& out, ErrorText& error) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    if (png) png_destroy_read_struct(&png, nullptr, nullptr);
    error.set("out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, &in, pngRead);
  // libpng allocates a text chunk whole from its length field before reading it: a corrupt
  // length (up to 2 GB) would be allocated before the read finds the data missing. Skipped
  // chunks are read through a small buffer instead; the profile of an iCCP chunk is bounded.
  png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, nullptr, 0);
  png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, kIgnoredPngChunks, kIgnoredPngChunkCount);
  png_set_chunk_malloc_max(png, kMaxPngChunkBytes);
  png_read_info(png, info);
  png_uint_32 width = 0, height = 0;
  int depth = 0, colour = 0;
  png_get_IHDR(png, info, &width, &height, &depth, &colour, nullptr, nullptr, nullptr);
  const bool transparent = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
  const bool has_colour = (colour & PNG_COLOR_MASK_COLOR) != 0;  // RGB, RGBA and palette
  int channels = 1;
  if (mode == ImageRead::kUnchanged) {
    if (colour == PNG_COLOR_TYPE_GRAY_ALPHA || colour == PNG_COLOR_TYPE_RGB_ALPHA)
      channels = 4;
    else if (has_colour)
      channels = transparent ? 4 : 3;
  }
  const bool sixteen = mode == ImageRead::kUnchanged && depth == 16;
  const uint64_t bytes = uint64_t{width} * height * static_cast<uint64_t>(channels) * (sixteen ? 2 : 1);
  if (bytes > kMaxImageBytes) png_error(png, "the header asks for an image larger than 512 MB");

  if (depth == 16) {
    if (sixteen)
      setPngByteOrder(png);
    else
      png_set_strip_16(png);  // keeps the high byte, as OpenCV does
  }
  if (channels < 4)
    png_set_strip_alpha(png);
  else
    png_set_tRNS_to_alpha(png);
  if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (!has_colour && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (channels > 1 && has_colour)
    png_set_bgr(png);
  else if (channels > 1)
    png_set_gray_to_rgb(png);
  else if (has_colour)
    png_set_rgb_to_gray(png, PNG_ERROR_ACTION_NONE, 0.299, 0.587);
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);
  const size_t row_bytes = static_cast<size_t>(width) * static_cast<size_t>(channels) * (sixteen ? 2 : 1);
  if (png_get_rowbytes(png, info) != row_bytes) png_error(png, "unexpected row layout after the transforms");

  out.create(static_cast<int>(height), static_cast<int>(width), CV_MAKETYPE(sixteen ? CV_16U : CV_8U, channels));
  for (int pass = 0; pass < passes; ++pass)
    for (int y = 0; y < out.rows; ++y) png_read_row(png, out.ptr<uint8_t>(y), nullptr);
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

void pngWrite(png_structp png, png_bytep data, png_size_t n) {
  auto* bytes = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
  bytes->insert(bytes->end(), data, data + n);
}

void pngFlush(png_structp) {}

bool encodePng(const cv::Mat& image, std::vector<uint8_t>& bytes, ErrorText& error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, pngError, pngWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    if (png) png_destroy_write_struct(&png, nullptr);
    error.set("out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &bytes, pngWrite, pngFlush);
  const int channels = image.channels();
  const int colour = channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA;
  const int depth = image.depth() == CV_16U ? 16 : 8;
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.cols), static_cast<png_uint_32>(image.rows), depth, colour,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  // Fast settings (OpenCV's defaults too): camera frames are written at the camera's rate.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  png_write_info(png, info);
  if (channels > 1) png_set_bgr(png);
  if (depth == 16) setPngByteOrder(png);
  for (int y = 0; y < image.rows; ++y) png_write_row(png, image.ptr<uint8_t>(y));
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

// ---- JPEG -----------------------------------------------------------------------------------

struct JpegErrors {
  jpeg_error_mgr manager;  // first: libjpeg hands back a pointer to it
  std::jmp_buf jump;
  ErrorText* error;
  bool truncated;
};

void jpegError(j_common_ptr info) {
  auto* errors = reinterpret_cast<JpegErrors*>(info->err);
  char message[JMSG_LENGTH_MAX];
  info->err->format_message(info, message);
  errors->error->set(message);
  std::longjmp(errors->jump, 1);
}

// Warnings are silent, except that a stream that ends early (libjpeg pads it with grey and
// carries on) is an error here: half an image must not pass for a frame.
void jpegMessage(j_common_ptr info, int level) {
  if (level < 0 && info->err->msg_code == JWRN_JPEG_EOF) reinterpret_cast<JpegErrors*>(info->err)->truncated = true;
}

// The error manager both directions share; the caller still calls setjmp (it must be the frame
// the longjmp returns to).
jpeg_error_mgr* jpegErrorManager(JpegErrors& errors, ErrorText& error) {
  jpeg_error_mgr* manager = jpeg_std_error(&errors.manager);
  manager->error_exit = jpegError;
  manager->emit_message = jpegMessage;
  errors.error = &error;
  errors.truncated = false;
  return manager;
}

// cv::imread's choices: grey is libjpeg's luminance output, colour its BGR output.
bool decodeJpeg(ImageInput& in, ImageRead mode, cv::Mat& out, ErrorText& error) {
  jpeg_decompress_struct cinfo;
  JpegErrors errors;
  cinfo.err = jpegErrorManager(errors, error);
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  if (in.file)
    jpeg_stdio_src(&cinfo, in.file);
  else
    jpeg_mem_src(&cinfo, in.data, static_cast<unsigned long>(in.size));
  jpeg_read_header(&cinfo, TRUE);
  const bool colour = mode == ImageRead::kUnchanged && cinfo.num_components > 1;
  cinfo.out_color_space = colour ? JCS_EXT_BGR : JCS_GRAYSCALE;
  jpeg_start_decompress(&cinfo);
  const int channels = colour ? 3 : 1;
  if (uint64_t{cinfo.output_width} * cinfo.output_height * static_cast<uint64_t>(channels) > kMaxImageBytes) {
    error.set("the header asks for an image larger than 512 MB");
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  out.create(static_cast<int>(cinfo.output_height), static_cast<int>(cinfo.output_width), colour ? CV_8UC3 : CV_8UC1);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = out.ptr<uint8_t>(static_cast<int>(cinfo.output_scanline));
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  if (errors.truncated) {
    error.set("the data ends before the image does (truncated)");
    return false;
  }
  return true;
}

struct JpegOutput {
  unsigned char* data = nullptr;  // malloc'ed by libjpeg
  unsigned long size = 0;
};

bool encodeJpeg(const cv::Mat& image, JpegOutput& output, ErrorText& error) {
  jpeg_compress_struct cinfo;
  JpegErrors errors;
  cinfo.err = jpegErrorManager(errors, error);
  if (setjmp(errors.jump)) {
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, &output.data, &output.size);
  cinfo.image_width = static_cast<JDIMENSION>(image.cols);
  cinfo.image_height = static_cast<JDIMENSION>(image.rows);
  cinfo.input_components = image.channels();
  cinfo.in_color_space = image.channels() == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, 95, TRUE);  // cv::imwrite's default quality
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<uint8_t*>(image.ptr<uint8_t>(static_cast<int>(cinfo.next_scanline)));
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

// ---- shared ---------------------------------------------------------------------------------

const char* const kOtherFormats = "image formats other than PNG and JPEG";

std::string lowercaseExtension(const std::string& extension) {
  std::string ext = extension;
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Decodes PNG or JPEG (recognised by their first bytes, `head`); false with `why` set otherwise,
// or `other` = true when the input is neither (for the media module to try).
bool decodeKnown(ImageInput& in, const uint8_t* head, size_t head_size, ImageRead mode, cv::Mat& out,
                 std::string& why, bool& other) {
  ErrorText error;
  other = false;
  if (isPng(head, head_size)) {
    if (decodePng(in, mode, out, error)) return true;
    why = std::string("not a readable PNG: ") + error.text;
  } else if (isJpeg(head, head_size)) {
    if (decodeJpeg(in, mode, out, error)) return true;
    why = std::string("not a readable JPEG: ") + error.text;
  } else {
    other = true;
  }
  out.release();
  return false;
}

// The whole file into *bytes: `head` (already read) and the rest. False on a read error or a
// file too large to be a frame (the streaming path then decodes or refuses it).
bool readRest(FILE* file, const uint8_t* head, size_t head_size, std::vector<uint8_t>* bytes) {
  struct stat st {};
  if (fstat(fileno(file), &st) != 0 || st.st_size < 0 || static_cast<uint64_t>(st.st_size) > kMaxImageBytes)
    return false;
  bytes->assign(head, head + head_size);
  bytes->resize(std::max(static_cast<size_t>(st.st_size), head_size));
  const size_t rest = bytes->size() - head_size;
  return std::fread(bytes->data() + head_size, 1, rest, file) == rest;
}

}  // namespace

cv::Mat readImageFile(const std::string& path, ImageRead mode) {
  const std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!file) throw InputError(path, 0, "", std::filesystem::exists(path) ? "cannot open" : "no such image file");
  uint8_t head[kGreyPngHeadBytes];
  const size_t head_size = std::fread(head, 1, sizeof head, file.get());
  if (head_size == 0) throw InputError(path, 0, "", "empty image file");
  if (isGreyPng(head, head_size)) {  // a camera frame: read whole, decoded with libdeflate
    thread_local std::vector<uint8_t> bytes;
    cv::Mat image;
    const bool decoded = readRest(file.get(), head, head_size, &bytes) &&
                         decodeGreyPng(bytes.data(), bytes.size(), mode, image);
    if (bytes.capacity() > kKeptBufferBytes) std::vector<uint8_t>().swap(bytes);
    if (decoded) return image;
  }
  std::rewind(file.get());
  ImageInput in;
  in.file = file.get();
  cv::Mat image;
  std::string why;
  bool other = false;
  if (decodeKnown(in, head, head_size, mode, image, why, other)) return image;
  if (!other) throw InputError(path, 0, "", why);
  image = requireMediaModule(path, "", std::string("reading ") + kOtherFormats).read_image(path, mode);
  if (image.empty()) throw InputError(path, 0, "", "neither PNG nor JPEG, and OpenCV cannot read it as an image");
  return image;
}

cv::Mat decodeImage(const std::vector<uint8_t>& bytes, ImageRead mode, std::string* why) {
  cv::Mat image;
  std::string reason;
  bool other = false;
  if (decodeGreyPng(bytes.data(), bytes.size(), mode, image)) return image;
  ImageInput in;
  in.data = bytes.data();
  in.size = bytes.size();
  if (decodeKnown(in, bytes.data(), bytes.size(), mode, image, reason, other)) return image;
  if (other) {
    try {
      image = requireMediaModule("", "", std::string("decoding ") + kOtherFormats).decode_image(bytes, mode);
      if (!image.empty()) return image;
      reason = "neither PNG nor JPEG, and OpenCV cannot decode it";
    } catch (const InputError& e) {
      reason = std::string("neither PNG nor JPEG: ") + e.what();
    }
  }
  if (why) *why = reason;
  return cv::Mat();
}

std::vector<uint8_t> encodeImage(const std::string& extension, const cv::Mat& image, const std::string& path_for_errors) {
  const std::string ext = lowercaseExtension(extension);
  if (image.empty()) throw InputError(path_for_errors, 0, "", "cannot write an empty image");
  const int channels = image.channels();
  const bool png = ext == ".png", jpeg = ext == ".jpg" || ext == ".jpeg";
  if (png || jpeg) {
    const bool depth_ok = image.depth() == CV_8U || (png && image.depth() == CV_16U);
    if (!depth_ok || (channels != 1 && channels != 3 && channels != 4))
      throw InputError(path_for_errors, 0, "",
                       "cannot write a " + std::to_string(channels) + "-channel image of depth " +
                           std::to_string(image.depth()) + " as " + ext);
  }
  ErrorText error;
  std::vector<uint8_t> bytes;
  if (png) {
    if (!encodePng(image, bytes, error)) throw InputError(path_for_errors, 0, "", std::string("PNG encoding failed: ") + error.text);
    return bytes;
  }
  if (jpeg) {
    cv::Mat source = image;
    if (channels == 4) cv::cvtColor(image, source, cv::COLOR_BGRA2BGR);
    JpegOutput output;
    const bool ok = encodeJpeg(source, output, error);
    if (ok) bytes.assign(output.data, output.data + output.size);
    std::free(output.data);
    if (!ok) throw InputError(path_for_errors, 0, "", std::string("JPEG encoding failed: ") + error.text);
    return bytes;
  }
  if (!requireMediaModule(path_for_errors, "", std::string("writing ") + kOtherFormats).encode_image(ext, image, bytes))
    throw InputError(path_for_errors, 0, "", "OpenCV cannot write an image as '" + ext + "'");
  return bytes;
}

void writeImageFile(const std::string& path, const cv::Mat& image) {
  const std::vector<uint8_t> bytes = encodeImage(std::filesystem::path(path).extension().string(), image, path);
  writeTextFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

}  // namespace adugs::data
