#include "spirv_reflection.h"

#include "vulkan_check.h"

#include <algorithm>
#include <unordered_map>

namespace ssvgi::gpu {

namespace {

// The few SPIR-V opcodes and enumerants reflection needs (SPIR-V specification, §3).
enum Op : uint32_t {
  OpName = 5, OpEntryPoint = 15, OpExecutionMode = 16, OpTypeBool = 20, OpTypeInt = 21, OpTypeFloat = 22,
  OpTypeVector = 23, OpTypeMatrix = 24, OpTypeImage = 25, OpTypeSampler = 26, OpTypeSampledImage = 27,
  OpTypeArray = 28, OpTypeRuntimeArray = 29, OpTypeStruct = 30, OpTypePointer = 32, OpConstant = 43, OpVariable = 59,
  OpDecorate = 71, OpMemberDecorate = 72,
};
enum Decoration : uint32_t {
  DecorationBlock = 2, DecorationBufferBlock = 3, DecorationArrayStride = 6, DecorationMatrixStride = 7,
  DecorationNonWritable = 24, DecorationOffset = 35, DecorationBinding = 33, DecorationDescriptorSet = 34,
};
enum StorageClass : uint32_t {
  StorageUniformConstant = 0, StorageUniform = 2, StoragePushConstant = 9, StorageStorageBuffer = 12,
};
constexpr uint32_t kExecutionModeLocalSize = 17;
constexpr uint32_t kSpirvMagic = 0x07230203;

struct Id {
  uint32_t opcode = 0;
  std::vector<uint32_t> operands;  // after the result id
  std::string name;
  int binding = -1;
  int set = -1;
  bool block = false;
  bool bufferBlock = false;
  bool nonWritable = false;
  uint32_t arrayStride = 0;
  std::vector<uint32_t> memberOffsets;
  std::vector<uint32_t> memberMatrixStrides;
  std::vector<bool> memberNonWritable;
  uint32_t constant = 0;
};

std::string readString(std::span<const uint32_t> words) {
  std::string text;
  for (uint32_t word : words) {
    for (int byte = 0; byte < 4; ++byte) {
      const char c = static_cast<char>((word >> (8 * byte)) & 0xff);
      if (c == '\0') return text;
      text += c;
    }
  }
  return text;
}

class Reflector {
 public:
  Reflector(std::span<const uint32_t> words, const std::string& shaderName) : shaderName_(shaderName) {
    if (words.size() < 5 || words[0] != kSpirvMagic) fail("not a SPIR-V module");
    ids_.resize(words[3]);
    for (size_t at = 5; at < words.size();) {
      const uint32_t opcode = words[at] & 0xffff;
      const uint32_t count = words[at] >> 16;
      if (count == 0 || at + count > words.size()) fail("truncated instruction");
      parse(opcode, words.subspan(at + 1, count - 1));
      at += count;
    }
  }

  ShaderReflection reflect() {
    for (const Id& id : ids_) {
      if (id.opcode != OpVariable) continue;
      const uint32_t storage = id.operands[1];
      const Id& pointer = ids_.at(id.operands[0]);
      uint32_t typeId = pointer.operands[1];
      if (storage == StoragePushConstant) {
        result_.pushConstantBytes = std::max(result_.pushConstantBytes, sizeOf(typeId));
        continue;
      }
      if (storage != StorageUniformConstant && storage != StorageUniform && storage != StorageStorageBuffer) continue;
      if (id.binding < 0) continue;
      if (id.set != 0) fail("binding '" + id.name + "' uses descriptor set " + std::to_string(id.set) + "; only set 0 is supported");

      ReflectedBinding binding;
      binding.binding = static_cast<uint32_t>(id.binding);
      binding.name = id.name;
      if (ids_.at(typeId).opcode == OpTypeArray) {
        binding.count = ids_.at(ids_.at(typeId).operands[1]).constant;
        typeId = ids_.at(typeId).operands[0];
      }
      const Id& type = ids_.at(typeId);
      if (binding.name.empty()) binding.name = type.name;
      switch (type.opcode) {
        case OpTypeStruct: {
          const bool storageBuffer = storage == StorageStorageBuffer || type.bufferBlock;
          binding.type = storageBuffer ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
          const bool allMembersReadOnly =
              !type.memberNonWritable.empty() &&
              std::all_of(type.memberNonWritable.begin(), type.memberNonWritable.end(), [](bool b) { return b; });
          binding.writable = storageBuffer && !(id.nonWritable || allMembersReadOnly);
          break;
        }
        case OpTypeImage: {
          const uint32_t sampled = type.operands[5];
          binding.type = sampled == 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
          binding.writable = sampled == 2 && !id.nonWritable;
          break;
        }
        case OpTypeSampledImage: binding.type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER; break;
        case OpTypeSampler: binding.type = VK_DESCRIPTOR_TYPE_SAMPLER; break;
        default: fail("binding '" + binding.name + "' has an unsupported descriptor type");
      }
      result_.bindings.push_back(binding);
    }
    std::sort(result_.bindings.begin(), result_.bindings.end(),
              [](const auto& a, const auto& b) { return a.binding < b.binding; });
    return result_;
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw GpuError("shader " + shaderName_ + ": " + problem);
  }

  Id& at(uint32_t id) {
    if (id >= ids_.size()) fail("id out of bounds");
    return ids_[id];
  }

  void parse(uint32_t opcode, std::span<const uint32_t> operands) {
    switch (opcode) {
      case OpName: at(operands[0]).name = readString(operands.subspan(1)); break;
      case OpEntryPoint: {
        const uint32_t model = operands[0];
        result_.stage = model == 0 ? VK_SHADER_STAGE_VERTEX_BIT
                        : model == 4 ? VK_SHADER_STAGE_FRAGMENT_BIT
                                     : VK_SHADER_STAGE_COMPUTE_BIT;
        break;
      }
      case OpExecutionMode:
        if (operands[1] == kExecutionModeLocalSize)
          for (int axis = 0; axis < 3; ++axis) result_.localSize[axis] = operands[2 + axis];
        break;
      case OpDecorate: {
        Id& target = at(operands[0]);
        switch (operands[1]) {
          case DecorationBinding: target.binding = static_cast<int>(operands[2]); break;
          case DecorationDescriptorSet: target.set = static_cast<int>(operands[2]); break;
          case DecorationBlock: target.block = true; break;
          case DecorationBufferBlock: target.bufferBlock = true; break;
          case DecorationNonWritable: target.nonWritable = true; break;
          case DecorationArrayStride: target.arrayStride = operands[2]; break;
          default: break;
        }
        break;
      }
      case OpMemberDecorate: {
        Id& target = at(operands[0]);
        const uint32_t member = operands[1];
        auto grow = [&](auto& list, auto fill) {
          if (list.size() <= member) list.resize(member + 1, fill);
        };
        if (operands[2] == DecorationOffset) grow(target.memberOffsets, 0u), target.memberOffsets[member] = operands[3];
        if (operands[2] == DecorationMatrixStride)
          grow(target.memberMatrixStrides, 0u), target.memberMatrixStrides[member] = operands[3];
        if (operands[2] == DecorationNonWritable) grow(target.memberNonWritable, false), target.memberNonWritable[member] = true;
        break;
      }
      case OpConstant:
        at(operands[1]).opcode = OpConstant;
        at(operands[1]).constant = operands.size() > 2 ? operands[2] : 0;
        break;
      case OpVariable:
        at(operands[1]).opcode = OpVariable;
        at(operands[1]).operands = {operands[0], operands[2]};
        break;
      case OpTypeBool: case OpTypeInt: case OpTypeFloat: case OpTypeVector: case OpTypeMatrix: case OpTypeImage:
      case OpTypeSampler: case OpTypeSampledImage: case OpTypeArray: case OpTypeRuntimeArray: case OpTypeStruct:
      case OpTypePointer: {
        Id& type = at(operands[0]);
        type.opcode = opcode;
        type.operands.assign(operands.begin() + 1, operands.end());
        if (opcode == OpTypeStruct) type.memberNonWritable.resize(type.operands.size(), false);
        break;
      }
      default: break;
    }
  }

  // Byte size of a type laid out with explicit offsets/strides (push constant blocks).
  uint32_t sizeOf(uint32_t typeId, uint32_t matrixStride = 16) {
    const Id& type = at(typeId);
    switch (type.opcode) {
      case OpTypeBool: return 4;
      case OpTypeInt:
      case OpTypeFloat: return type.operands[0] / 8;
      case OpTypeVector: return type.operands[1] * sizeOf(type.operands[0]);
      case OpTypeMatrix: return type.operands[1] * matrixStride;
      case OpTypeArray: return at(type.operands[1]).constant * type.arrayStride;
      case OpTypeStruct: {
        uint32_t size = 0;
        for (size_t member = 0; member < type.operands.size(); ++member) {
          const uint32_t offset = member < type.memberOffsets.size() ? type.memberOffsets[member] : 0;
          const uint32_t stride = member < type.memberMatrixStrides.size() && type.memberMatrixStrides[member]
                                      ? type.memberMatrixStrides[member]
                                      : 16;
          size = std::max(size, offset + sizeOf(type.operands[member], stride));
        }
        return size;
      }
      default: fail("unsupported type in a push constant block");
    }
  }

  std::string shaderName_;
  std::vector<Id> ids_;
  ShaderReflection result_;
};

}  // namespace

ShaderReflection reflectSpirv(std::span<const uint32_t> words, const std::string& shaderName) {
  return Reflector(words, shaderName).reflect();
}

}  // namespace ssvgi::gpu
