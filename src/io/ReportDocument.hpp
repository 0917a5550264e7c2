// The report schema: which keys a pkm_verify report holds and what each says (the list is in the header of
// include/pkm_accuracy/io/ResultWriter.hpp and in docs/cli.md). Internal to the io library: toJson / toYaml write
// this one tree.
#pragma once

#include "DocumentNode.hpp"
#include "pkm_accuracy/core/verify/VerifierOptions.hpp"
#include "pkm_accuracy/core/verify/VerifierResult.hpp"
#include "pkm_accuracy/io/ResultWriter.hpp"

namespace pkm_accuracy {
namespace io {

/// The whole report of a run as one object: every key always present (null where it does not apply), in the order of
/// the schema.
DocumentNode reportDocument(const verify::VerifierResult& result, const verify::VerifierOptions& options,
                            const RunInfo& info);

}  // namespace io
}  // namespace pkm_accuracy
