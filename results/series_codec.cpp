#include "results/series_codec.hpp"

#include "results/store_error.hpp"

#include <zstd.h>

#include <cstring>
#include <memory>

namespace armfarm {
namespace {

static_assert(sizeof(double) == 8, "float64 expected");
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "series_codec assumes a little-endian host; add byte swapping for big-endian ones"
#endif

constexpr int kZstdLevel = 3;

}  // namespace

std::vector<unsigned char> calc_series_blob(const Eigen::MatrixXd& rows) {
  const std::size_t raw_bytes = static_cast<std::size_t>(rows.size()) * sizeof(double);
  std::vector<unsigned char> blob(ZSTD_compressBound(raw_bytes));
  // The frame carries zstd's content checksum (XXH64 of the samples, 4 bytes): a flipped bit in
  // the stored BLOB makes decompression fail instead of yielding other numbers.
  const std::unique_ptr<ZSTD_CCtx, std::size_t (*)(ZSTD_CCtx*)> context(ZSTD_createCCtx(), ZSTD_freeCCtx);
  if (!context) throw StoreError("zstd compression failed: no memory for a context");
  ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, kZstdLevel);
  ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
  const std::size_t size = ZSTD_compress2(context.get(), blob.data(), blob.size(), rows.data(), raw_bytes);
  if (ZSTD_isError(size)) throw StoreError(std::string("zstd compression failed: ") + ZSTD_getErrorName(size));
  blob.resize(size);
  return blob;
}

Eigen::MatrixXd calc_series_matrix(const std::vector<unsigned char>& blob, long n_rows, long n_columns,
                                   const std::string& where) {
  if (n_rows < 0 || n_columns < 0) throw StoreError(where + ": negative series size");
  Eigen::MatrixXd rows(n_rows, n_columns);
  const std::size_t raw_bytes = static_cast<std::size_t>(rows.size()) * sizeof(double);
  const unsigned long long content = ZSTD_getFrameContentSize(blob.data(), blob.size());
  if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN || content != raw_bytes) {
    throw StoreError(where + ": series data is not a zstd frame of " + std::to_string(raw_bytes) + " bytes");
  }
  const std::size_t size = ZSTD_decompress(rows.data(), raw_bytes, blob.data(), blob.size());
  // ZSTD_decompress verifies the frame's content checksum when the frame has one (every BLOB
  // written since issue 30; older ones are checked by their size only).
  if (ZSTD_isError(size) || size != raw_bytes) {
    throw StoreError(where + ": corrupt series data (" +
                     (ZSTD_isError(size) ? std::string(ZSTD_getErrorName(size)) : std::string("short frame")) + ")");
  }
  return rows;
}

}  // namespace armfarm
