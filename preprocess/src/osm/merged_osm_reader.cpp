#include <memory>
#include <osmium/io/any_input.hpp>
#include <osmium/osm/object.hpp>
#include <string>
#include <tuple>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/osm/osm_pass.hpp"

namespace roadcross::preprocess {

namespace {

/// osmium's object order without version and timestamp: type, then positive ids before
/// negative ones, then by absolute id (as `osmium sort` orders a file).
auto order_key(const osmium::OSMObject& object) {
  return std::make_tuple(object.type(), object.id() > 0, object.positive_id());
}

std::string describe(const osmium::OSMObject& object) {
  return std::string(osmium::item_type_to_name(object.type())) + " " + std::to_string(object.id());
}

}  // namespace

/// One file of the merge: its reader and the object it stands at.
class MergedOsmReader::Input {
 public:
  Input(const std::string& path, osmium::osm_entity_bits::type entities)
      : path_(path), reader_(open(path, entities)) {
    advance();
  }
  ~Input() {
    // close() may throw (a worker thread's error); the destructor only runs on the way out
    // of an error already being reported, or after the end of the file was read.
    try {
      reader_->close();
    } catch (...) {
    }
  }

  /// The object the file stands at, nullptr at its end.
  osmium::OSMObject* current() const { return current_; }

  /// Moves to the file's next object, checking that the file is sorted.
  void advance() {
    current_ = nullptr;
    for (;;) {
      if (buffer_ && it_ != buffer_.end<osmium::OSMObject>()) {
        current_ = &*it_;
        ++it_;
        break;
      }
      try {
        buffer_ = reader_->read();
      } catch (const std::exception& e) {
        // libosmium's XML errors already say "XML parsing error at line L, column C: ...".
        throw InputError(path_, std::string("not readable as OSM data: ") + e.what());
      }
      if (!buffer_) return;
      it_ = buffer_.begin<osmium::OSMObject>();
    }
    if (has_previous_ && order_key(*current_) < previous_key_) {
      throw InputError(path_, describe(*current_) + " comes after " +
                                  osmium::item_type_to_name(std::get<0>(previous_key_)) + " " +
                                  std::to_string(previous_id_) +
                                  ": the file is not sorted by type and id, which merging "
                                  "several --osm inputs needs (sort it with `osmium sort`)");
    }
    has_previous_ = true;
    previous_key_ = order_key(*current_);
    previous_id_ = current_->id();
  }

  std::uint64_t offset() const { return reader_->offset(); }
  std::uint64_t size() const { return reader_->file_size(); }

 private:
  static std::unique_ptr<osmium::io::Reader> open(const std::string& path,
                                                  osmium::osm_entity_bits::type entities) {
    try {
      return std::make_unique<osmium::io::Reader>(osmium::io::File{path}, entities,
                                                  osm_decoder_pool());
    } catch (const std::exception& e) {
      throw InputError(path, std::string("not readable as OSM data: ") + e.what());
    }
  }

  std::string path_;
  std::unique_ptr<osmium::io::Reader> reader_;
  osmium::memory::Buffer buffer_;
  osmium::memory::Buffer::t_iterator<osmium::OSMObject> it_;
  osmium::OSMObject* current_ = nullptr;
  bool has_previous_ = false;
  ObjectKey previous_key_{};
  osmium::object_id_type previous_id_ = 0;
};

MergedOsmReader::MergedOsmReader(const std::vector<std::string>& paths,
                                 osmium::osm_entity_bits::type entities) {
  for (const std::string& path : paths) {
    inputs_.push_back(std::make_unique<Input>(path, entities));
    size_ += inputs_.back()->size();
  }
}

MergedOsmReader::~MergedOsmReader() = default;

std::uint64_t MergedOsmReader::offset() const {
  std::uint64_t sum = 0;
  for (const auto& input : inputs_) sum += input->offset();
  return sum;
}

osmium::OSMObject* MergedOsmReader::next() {
  // Every copy of the object handed on last (in the other files, and further versions in a
  // history file) is skipped: it went on once.
  if (last_) {
    for (const auto& input : inputs_) {
      while (input->current() && order_key(*input->current()) == *last_) input->advance();
    }
  }
  // The smallest (type, id) of all files' current objects; of equal ones the newest version,
  // the earlier file on a tie. Few files, so a linear scan.
  osmium::OSMObject* chosen = nullptr;
  for (const auto& input : inputs_) {
    osmium::OSMObject* object = input->current();
    if (!object) continue;
    if (!chosen || order_key(*object) < order_key(*chosen) ||
        (order_key(*object) == order_key(*chosen) && object->version() > chosen->version())) {
      chosen = object;
    }
  }
  if (!chosen) return nullptr;
  last_ = order_key(*chosen);
  return chosen;
}

}  // namespace roadcross::preprocess
