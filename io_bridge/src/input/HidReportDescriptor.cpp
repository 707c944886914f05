// HID report-descriptor parser: Device Class Definition for HID 1.11, §6.2.2 (items), with the
// Linux HID core's readings where the spec is ambiguous (drivers/hid/hid-core.c):
//  - a Logical/Physical Maximum is signed only when the matching minimum is negative;
//  - a Unit Exponent that fits in 4 bits is a 4-bit two's-complement nibble;
//  - a 1- or 2-byte Usage takes the Usage Page current when it is parsed, and usages at the end of
//    the local list take the last Usage Page if it was declared after them (hid_concatenate_last_usage_page);
//  - a main item without usages is padding.
#include <io_bridge/HidReportDescriptor.h>

#include "SystemError.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

namespace fieldcast::io {
namespace {

enum class ItemType : std::uint8_t { Main = 0, Global = 1, Local = 2, Reserved = 3 };

struct Globals {
  std::uint16_t usagePage = 0;
  std::int32_t logicalMin = 0;
  std::int32_t logicalMax = 0;
  std::int32_t physicalMin = 0;
  std::int32_t physicalMax = 0;
  std::int32_t unitExponent = 0;
  std::uint32_t unit = 0;
  std::uint32_t reportSize = 0;
  std::uint32_t reportCount = 0;
  std::uint8_t reportId = 0;
};

struct LocalUsage {
  Usage usage = 0;
  bool explicitPage = false;  // a 4-byte Usage carries its own page
};

struct Locals {
  std::vector<LocalUsage> usages;
  bool haveUsageMin = false;
  std::uint32_t usageMin = 0;
  bool usageMinExplicit = false;
  int delimiterDepth = 0;
  int delimiterBranch = 0;
  void clear() {
    usages.clear();
    haveUsageMin = false;
    delimiterDepth = 0;
    delimiterBranch = 0;
  }
};

std::string hex(std::uint32_t v) {
  std::array<char, 16> buf{};
  std::snprintf(buf.data(), buf.size(), "0x%x", v);
  return buf.data();
}

class Parser {
 public:
  explicit Parser(std::span<const std::uint8_t> bytes) : mBytes(bytes) {}

  HidReportDescriptor run() {
    if (mBytes.empty()) throw HidDescriptorError(0, "empty report descriptor");
    std::size_t pos = 0;
    while (pos < mBytes.size()) {
      const std::size_t start = pos;
      const std::uint8_t prefix = mBytes[pos++];
      if (prefix == 0xFE) {  // long item: bDataSize, bLongItemTag, data (reserved, skipped)
        if (pos + 2 > mBytes.size()) throw HidDescriptorError(start, "long item header runs past the end");
        const std::size_t size = mBytes[pos];
        pos += 2;
        if (pos + size > mBytes.size()) throw HidDescriptorError(start, "long item data runs past the end");
        pos += size;
        continue;
      }
      static constexpr std::array<std::size_t, 4> kSizes{0, 1, 2, 4};
      const std::size_t size = kSizes[prefix & 0x3u];
      if (pos + size > mBytes.size()) {
        throw HidDescriptorError(start, "item " + hex(prefix) + " needs " + std::to_string(size) +
                                            " data bytes, descriptor ends after " +
                                            std::to_string(mBytes.size() - pos));
      }
      std::uint32_t udata = 0;
      for (std::size_t i = 0; i < size; ++i) udata |= std::uint32_t{mBytes[pos + i]} << (8 * i);
      // Two's complement of the item's own width.
      std::int32_t sdata = 0;
      switch (size) {
        case 1:
          sdata = (udata & 0x80u) != 0 ? static_cast<std::int32_t>(udata) - 0x100 : static_cast<std::int32_t>(udata);
          break;
        case 2:
          sdata =
              (udata & 0x8000u) != 0 ? static_cast<std::int32_t>(udata) - 0x10000 : static_cast<std::int32_t>(udata);
          break;
        case 4: sdata = static_cast<std::int32_t>(udata); break;
        default: break;
      }
      pos += size;
      mItemOffset = start;
      const auto type = static_cast<ItemType>((prefix >> 2) & 0x3u);
      const std::uint8_t tag = prefix >> 4;
      switch (type) {
        case ItemType::Main: mainItem(tag, udata); break;
        case ItemType::Global: globalItem(tag, udata, sdata, size); break;
        case ItemType::Local: localItem(tag, udata, size); break;
        case ItemType::Reserved: throw HidDescriptorError(start, "reserved item type in prefix " + hex(prefix));
      }
    }
    if (!mOpen.empty()) {
      throw HidDescriptorError(mBytes.size(),
                               std::to_string(mOpen.size()) + " collection(s) not closed at the end of the descriptor");
    }
    if (mOut.usesReportIds && mFirstUnnumberedMain != kNone) {
      throw HidDescriptorError(mFirstUnnumberedMain,
                               "main item belongs to no report, but the descriptor uses Report IDs");
    }
    return std::move(mOut);
  }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  [[noreturn]] void fail(const std::string& reason) const { throw HidDescriptorError(mItemOffset, reason); }

  void globalItem(std::uint8_t tag, std::uint32_t udata, std::int32_t sdata, std::size_t size) {
    Globals& g = mGlobals;
    switch (tag) {
      case 0x0:
        if (udata > 0xFFFF) fail("Usage Page " + hex(udata) + " does not fit in 16 bits");
        g.usagePage = static_cast<std::uint16_t>(udata);
        break;
      case 0x1: g.logicalMin = sdata; break;
      case 0x2: g.logicalMax = g.logicalMin < 0 ? sdata : static_cast<std::int32_t>(udata); break;
      case 0x3: g.physicalMin = sdata; break;
      case 0x4: g.physicalMax = g.physicalMin < 0 ? sdata : static_cast<std::int32_t>(udata); break;
      case 0x5:
        // A value that fits in the low nibble is a 4-bit two's-complement exponent (HID 1.11 §6.2.2.7).
        g.unitExponent = (static_cast<std::uint32_t>(sdata) & 0xFFFFFFF0u) == 0 && size > 0
                             ? (sdata & 0x8 ? sdata - 16 : sdata)
                             : sdata;
        break;
      case 0x6: g.unit = udata; break;
      case 0x7:
        if (udata > hidlimits::kMaxReportSizeBits) {
          fail("Report Size " + std::to_string(udata) + " bits exceeds " +
               std::to_string(hidlimits::kMaxReportSizeBits));
        }
        g.reportSize = udata;
        break;
      case 0x8:
        if (udata == 0 || udata > 255) fail("Report ID " + std::to_string(udata) + " is outside 1..255");
        g.reportId = static_cast<std::uint8_t>(udata);
        mOut.usesReportIds = true;
        break;
      case 0x9:
        if (udata > hidlimits::kMaxReportCount) {
          fail("Report Count " + std::to_string(udata) + " exceeds " + std::to_string(hidlimits::kMaxReportCount));
        }
        g.reportCount = udata;
        break;
      case 0xA:
        if (mStack.size() >= hidlimits::kMaxGlobalStack) fail("Push nests deeper than the global stack (16)");
        mStack.push_back(g);
        break;
      case 0xB:
        if (mStack.empty()) fail("Pop with an empty global stack");
        g = mStack.back();
        mStack.pop_back();
        break;
      default: fail("unknown Global item tag " + hex(tag));
    }
  }

  void addUsage(std::uint32_t data, std::size_t size) {
    if (mLocals.delimiterDepth > 0 && mLocals.delimiterBranch > 1) return;  // alternates: keep the first
    if (mLocals.usages.size() >= hidlimits::kMaxUsagesPerItem) {
      fail("more than " + std::to_string(hidlimits::kMaxUsagesPerItem) + " usages before one main item");
    }
    if (size == 4) {
      mLocals.usages.push_back({data, true});
    } else {
      mLocals.usages.push_back({makeUsage(mGlobals.usagePage, static_cast<std::uint16_t>(data)), false});
    }
  }

  void localItem(std::uint8_t tag, std::uint32_t udata, std::size_t size) {
    switch (tag) {
      case 0x0: addUsage(udata, size); break;
      case 0x1:
        mLocals.haveUsageMin = true;
        mLocals.usageMin = udata;
        mLocals.usageMinExplicit = size == 4;
        break;
      case 0x2: {
        if (!mLocals.haveUsageMin) fail("Usage Maximum without a Usage Minimum");
        std::uint32_t first = mLocals.usageMin;
        std::uint32_t last = udata;
        if (mLocals.usageMinExplicit || size == 4) {
          if (size == 4 && mLocals.usageMinExplicit && (first >> 16) != (last >> 16)) {
            fail("Usage Minimum and Maximum on different usage pages");
          }
          first &= 0xFFFFu;
          last &= 0xFFFFu;
        }
        if (last > 0xFFFF || first > 0xFFFF) fail("Usage Minimum/Maximum does not fit in 16 bits");
        if (first > last) fail("Usage Minimum " + hex(first) + " > Usage Maximum " + hex(last));
        const std::uint32_t page = (mLocals.usageMinExplicit ? mLocals.usageMin : (size == 4 ? udata : 0)) >> 16;
        for (std::uint32_t u = first; u <= last; ++u) {
          if (page != 0 || mLocals.usageMinExplicit || size == 4) {
            addUsage((page << 16) | u, 4);
          } else {
            addUsage(u, 2);
          }
        }
        mLocals.haveUsageMin = false;
        break;
      }
      case 0xA:  // Delimiter: 1 opens a set of alternative usages, 0 closes it
        if (udata == 1) {
          if (mLocals.delimiterDepth > 0) fail("nested Delimiter");
          mLocals.delimiterDepth = 1;
          ++mLocals.delimiterBranch;
        } else if (udata == 0) {
          if (mLocals.delimiterDepth == 0) fail("Delimiter close without open");
          mLocals.delimiterDepth = 0;
        } else {
          fail("Delimiter value " + std::to_string(udata) + " is neither 0 nor 1");
        }
        break;
      default: break;  // designators and strings do not affect decoding
    }
  }

  // Usages parsed before a later Usage Page take that page (see the file comment).
  void concatenateLastUsagePage() {
    for (auto it = mLocals.usages.rbegin(); it != mLocals.usages.rend(); ++it) {
      if (it->explicitPage) continue;
      if (usagePage(it->usage) == mGlobals.usagePage) break;
      it->usage = makeUsage(mGlobals.usagePage, usageId(it->usage));
    }
  }

  Usage currentApplication() const {
    for (auto it = mOpen.rbegin(); it != mOpen.rend(); ++it) {
      if (mOut.collections[static_cast<std::size_t>(*it)].type == 1) {
        return mOut.collections[static_cast<std::size_t>(*it)].usage;
      }
    }
    return 0;
  }

  void mainItem(std::uint8_t tag, std::uint32_t udata) {
    if (mLocals.delimiterDepth > 0) fail("main item inside an open Delimiter");
    if (mLocals.haveUsageMin) fail("Usage Minimum without a Usage Maximum");
    concatenateLastUsagePage();
    switch (tag) {
      case 0x8: addField(HidReportType::Input, udata); break;
      case 0x9: addField(HidReportType::Output, udata); break;
      case 0xB: addField(HidReportType::Feature, udata); break;
      case 0xA: {
        if (mOpen.size() >= hidlimits::kMaxCollectionDepth) fail("collections nest deeper than 64");
        HidCollection c;
        c.type = static_cast<std::uint8_t>(udata & 0xFF);
        c.usage = mLocals.usages.empty() ? 0 : mLocals.usages.front().usage;
        c.parent = mOpen.empty() ? -1 : mOpen.back();
        mOut.collections.push_back(c);
        mOpen.push_back(static_cast<int>(mOut.collections.size() - 1));
        break;
      }
      case 0xC:
        if (mOpen.empty()) fail("End Collection without an open Collection");
        mOpen.pop_back();
        break;
      default: break;  // reserved main tags are ignored, as the kernel does
    }
    mLocals.clear();
  }

  void addField(HidReportType type, std::uint32_t flags) {
    const Globals& g = mGlobals;
    const bool rangeValid = g.logicalMin < 0
                                ? g.logicalMax >= g.logicalMin
                                : static_cast<std::uint32_t>(g.logicalMax) >= static_cast<std::uint32_t>(g.logicalMin);
    const bool hasUsages = !mLocals.usages.empty();
    if (hasUsages && !rangeValid) {
      fail("Logical Maximum " + std::to_string(g.logicalMax) + " < Logical Minimum " + std::to_string(g.logicalMin));
    }
    if (g.reportId == 0 && mFirstUnnumberedMain == kNone) mFirstUnnumberedMain = mItemOffset;

    HidReportInfo* report = findOrAddReport(type, g.reportId);
    const std::uint64_t bits = std::uint64_t{g.reportSize} * g.reportCount;
    const std::uint32_t offset = report->bitLength;
    if (report->bitLength + bits > (std::uint64_t{hidlimits::kMaxReportBytes} - 1) * 8) {
      fail("report " + std::to_string(g.reportId) + " grows beyond " + std::to_string(hidlimits::kMaxReportBytes) +
           " bytes");
    }
    report->bitLength = static_cast<std::uint32_t>(report->bitLength + bits);
    if (!hasUsages || g.reportCount == 0 || g.reportSize == 0) return;  // padding

    HidField f;
    f.type = type;
    f.reportId = g.reportId;
    f.bitOffset = offset;
    f.bitSize = g.reportSize;
    f.count = g.reportCount;
    f.flags = flags;
    f.logicalMin = g.logicalMin;
    f.logicalMax = g.logicalMax;
    if (g.physicalMin == 0 && g.physicalMax == 0) {
      f.physicalMin = g.logicalMin;
      f.physicalMax = g.logicalMax;
    } else {
      f.physicalMin = g.physicalMin;
      f.physicalMax = g.physicalMax;
    }
    f.unit = g.unit;
    f.unitExponent = g.unitExponent;
    f.application = currentApplication();
    const std::size_t usageCount = f.isVariable() ? f.count : mLocals.usages.size();
    if (mUsageTotal + usageCount > hidlimits::kMaxUsagesPerDescriptor) {
      fail("the descriptor declares more than " + std::to_string(hidlimits::kMaxUsagesPerDescriptor) + " usages");
    }
    mUsageTotal += usageCount;
    if (f.isVariable()) {
      // One usage per element; a short list repeats its last usage (HID 1.11 §6.2.2.8).
      f.usages.reserve(f.count);
      for (std::uint32_t i = 0; i < f.count; ++i) {
        f.usages.push_back(mLocals.usages[std::min<std::size_t>(i, mLocals.usages.size() - 1)].usage);
      }
    } else {
      f.usages.reserve(mLocals.usages.size());
      for (const LocalUsage& u : mLocals.usages) f.usages.push_back(u.usage);
    }
    mOut.fields.push_back(std::move(f));
  }

  HidReportInfo* findOrAddReport(HidReportType type, std::uint8_t id) {
    for (HidReportInfo& r : mOut.reports) {
      if (r.type == type && r.id == id) return &r;
    }
    mOut.reports.push_back(HidReportInfo{type, id, 0});
    return &mOut.reports.back();
  }

  std::span<const std::uint8_t> mBytes;
  std::size_t mItemOffset = 0;
  std::size_t mFirstUnnumberedMain = kNone;
  std::size_t mUsageTotal = 0;  // over all fields so far
  Globals mGlobals;
  std::vector<Globals> mStack;
  Locals mLocals;
  std::vector<int> mOpen;  // indices of open collections
  HidReportDescriptor mOut;
};

}  // namespace

HidDescriptorError::HidDescriptorError(std::size_t offset, const std::string& reason)
    : std::runtime_error("HID report descriptor, byte " + std::to_string(offset) + ": " + reason), mOffset(offset) {}

const HidReportInfo* HidReportDescriptor::report(HidReportType type, std::uint8_t id) const noexcept {
  for (const HidReportInfo& r : reports) {
    if (r.type == type && r.id == id) return &r;
  }
  return nullptr;
}

std::size_t HidReportDescriptor::maxInputReportBytes() const noexcept {
  std::size_t most = 0;
  for (const HidReportInfo& r : reports) {
    if (r.type == HidReportType::Input) most = std::max(most, r.wireBytes(usesReportIds));
  }
  return most;
}

HidReportDescriptor parseHidReportDescriptor(std::span<const std::uint8_t> bytes) { return Parser(bytes).run(); }

namespace {

// Descriptors are at most 4 KiB (HID_MAX_DESCRIPTOR_SIZE); a commented dump of one is far below this.
constexpr std::size_t kMaxDescriptorFileBytes = 1 << 20;

// A file is text when it holds no control byte but tab, line feed, form feed and carriage return
// (bytes of 0x80 and up are allowed: UTF-8 in comments). Every real binary descriptor has control
// bytes: it opens with a Usage Page item (0x05 0x01 …) and ends with End Collection (0xC0).
bool looksLikeText(std::string_view bytes) {
  if (bytes.empty()) return false;
  for (const char c : bytes) {
    const auto b = static_cast<unsigned char>(c);
    if ((b < 0x20 && b != '\t' && b != '\n' && b != '\r' && b != '\f' && b != '\v') || b == 0x7F) return false;
  }
  return true;
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// One word of hex: "0x5", "0x05", "05", or a run of pairs "050109" (xxd -p). Appends its bytes;
// false when the word is anything else.
bool appendHexWord(std::string_view w, std::vector<std::uint8_t>& out) {
  if (w.size() > 2 && w[0] == '0' && (w[1] == 'x' || w[1] == 'X')) {
    w.remove_prefix(2);
    if (w.size() > 2) return false;
    int v = 0;
    for (const char c : w) {
      if (hexDigit(c) < 0) return false;
      v = v * 16 + hexDigit(c);
    }
    out.push_back(static_cast<std::uint8_t>(v));
    return true;
  }
  if (w.empty() || w.size() % 2 != 0) return false;
  for (std::size_t i = 0; i < w.size(); i += 2) {
    const int hi = hexDigit(w[i]);
    const int lo = hexDigit(w[i + 1]);
    if (hi < 0 || lo < 0) return false;
    out.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
  }
  return true;
}

std::vector<std::string_view> splitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    lines.push_back(text.substr(0, end));
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
  return lines;
}

std::string_view trimmed(std::string_view s) {
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

std::string lineError(const std::string& path, std::size_t line, const std::string& what) {
  return path + ":" + std::to_string(line) + ": " + what;
}

// hid-recorder / hid-decode (hid-tools): "R: <length> <hex bytes…>" holds the descriptor; the other
// lines (# comments with the decoded items, N:, I:, P:, E: events) are ignored.
std::vector<std::uint8_t> parseRecorderLine(const std::string& path, std::size_t lineNo, std::string_view body) {
  std::istringstream words{std::string(body)};
  std::string lengthWord;
  words >> lengthWord;
  std::size_t used = 0;
  unsigned long length = 0;
  try {
    length = std::stoul(lengthWord, &used, 10);
  } catch (const std::exception&) {
    used = 0;
  }
  if (lengthWord.empty() || used != lengthWord.size()) {
    throw std::runtime_error(
        lineError(path, lineNo, "R: expected the descriptor length, then its bytes, got \"" + lengthWord + "\""));
  }
  std::vector<std::uint8_t> out;
  std::string w;
  while (words >> w) {
    if (w.size() != 2 || !appendHexWord(w, out)) {
      throw std::runtime_error(lineError(path, lineNo, "R: \"" + w + "\" is not a hex byte"));
    }
  }
  if (out.size() != length) {
    throw std::runtime_error(lineError(
        path, lineNo, "R: says " + std::to_string(length) + " bytes, the line holds " + std::to_string(out.size())));
  }
  return out;
}

// Hex text: byte pairs with optional 0x prefixes, separated by spaces or commas, with # and //
// comments to the end of the line and /* */ comments (hid-decode, usbhid-dump, kernel sources).
std::vector<std::uint8_t> parseHexText(const std::string& path, std::string_view text) {
  const std::vector<std::string_view> lines = splitLines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string_view line = trimmed(lines[i]);
    if (line.substr(0, 2) == "R:") {
      for (std::size_t j = i + 1; j < lines.size(); ++j) {
        if (trimmed(lines[j]).substr(0, 2) == "R:") {
          throw std::runtime_error(lineError(path, j + 1,
                                             "a second R: line (a recording of several devices): keep one "
                                             "device's R: line"));
        }
      }
      return parseRecorderLine(path, i + 1, line.substr(2));
    }
  }
  std::vector<std::uint8_t> out;
  bool inBlockComment = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::string_view line = lines[i];
    std::string code;  // the line without its comments
    while (!line.empty()) {
      if (inBlockComment) {
        const std::size_t close = line.find("*/");
        if (close == std::string_view::npos) break;
        inBlockComment = false;
        line.remove_prefix(close + 2);
        continue;
      }
      const std::size_t hash = line.find('#');
      const std::size_t slashes = line.find("//");
      const std::size_t block = line.find("/*");
      const std::size_t first = std::min({hash, slashes, block});
      code.append(line.substr(0, first));
      code += ' ';
      if (first == std::string_view::npos || first != block) break;  // # or //: the rest is comment
      inBlockComment = true;
      line.remove_prefix(block + 2);
    }
    // usbhid-dump heads each descriptor with "BBB:DDD:III:DESCRIPTOR  <timestamp>".
    if (code.find(":DESCRIPTOR") != std::string::npos) continue;
    std::replace(code.begin(), code.end(), ',', ' ');
    std::istringstream words(code);
    std::string w;
    while (words >> w) {
      if (!appendHexWord(w, out)) {
        throw std::runtime_error(
            lineError(path, i + 1, "\"" + w + "\" is not a hex byte (expected pairs such as 05 01 or 0x05, 0x01)"));
      }
    }
  }
  if (inBlockComment) throw std::runtime_error(path + ": a /* comment is not closed");
  if (out.empty()) throw std::runtime_error(path + ": no descriptor bytes in this text (only comments or blank lines)");
  return out;
}

}  // namespace

std::vector<std::uint8_t> readHidDescriptorFile(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path + ": is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot read the report descriptor: " + errnoMessage(errno));
  std::string bytes;
  std::array<char, 4096> chunk{};
  // Read in chunks with a cap, so a device node or a huge file is refused instead of swallowed.
  while (in.read(chunk.data(), chunk.size()) || in.gcount() > 0) {
    bytes.append(chunk.data(), static_cast<std::size_t>(in.gcount()));
    if (bytes.size() > kMaxDescriptorFileBytes) {
      throw std::runtime_error(path + ": more than " + std::to_string(kMaxDescriptorFileBytes) +
                               " bytes: not a report descriptor");
    }
  }
  if (in.bad()) throw std::runtime_error(path + ": read error: " + errnoMessage(errno));
  if (bytes.empty()) throw std::runtime_error(path + ": empty file");
  if (looksLikeText(bytes)) return parseHexText(path, bytes);
  return {bytes.begin(), bytes.end()};
}

std::string describeHidUnit(std::uint32_t unit, std::int32_t exponent) {
  if (unit == 0) return "none";
  // Nibble 0: system; nibbles 1..6: exponents of length, mass, time, temperature, current, luminosity.
  const std::uint32_t system = unit & 0xF;
  auto nibble = [&](int i) {
    const std::int32_t n = static_cast<std::int32_t>((unit >> (4 * i)) & 0xF);
    return n >= 8 ? n - 16 : n;
  };
  static constexpr std::array<std::string_view, 5> kSystems{"none", "SI linear", "SI rotation", "English linear",
                                                            "English rotation"};
  static constexpr std::array<std::array<std::string_view, 5>, 7> kNames{{
      {"", "", "", "", ""},
      {"", "cm", "rad", "in", "deg"},
      {"", "g", "g", "slug", "slug"},
      {"", "s", "s", "s", "s"},
      {"", "K", "K", "F", "F"},
      {"", "A", "A", "A", "A"},
      {"", "cd", "cd", "cd", "cd"},
  }};
  if (system > 4) return "unit " + hex(unit);
  std::string out;
  for (int i = 1; i <= 6; ++i) {
    const int e = nibble(i);
    if (e == 0) continue;
    if (!out.empty()) out += "·";
    out += kNames[static_cast<std::size_t>(i)][system];
    if (e != 1) {
      out += '^';
      out += std::to_string(e);
    }
  }
  if (out.empty()) out = std::string(kSystems[system]);
  if (exponent != 0) {
    out += " ×1e";
    out += std::to_string(exponent);
  }
  return out;
}

}  // namespace fieldcast::io
