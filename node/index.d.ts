// SPDX-License-Identifier: MIT
// Types of omnislice/node (node/index.mjs): the embedding module's API in Node, sliceFile also
// taking a file path.
import type { Settings, Progress } from '../wasm/omnislice';
import type { SliceFileResult, Slicer } from '../web/omnislice-embed';

export {
  OmnisliceError, createSlicer, PLACEMENT_KEYS, programFileName, sharedSlicer, disposeSharedSlicer, programBlob,
} from '../web/omnislice-embed';
export type { SliceFileResult, Slicer };

/** Slice one file: a path (or file URL), a Blob or {name, bytes}. */
export function sliceFile(
  file: string | URL | Blob | { name: string; bytes: ArrayBuffer | ArrayBufferView },
  settings?: Settings,
  options?: { onProgress?: (p: Progress) => void; signal?: AbortSignal; slicer?: Slicer; name?: string },
): Promise<SliceFileResult>;
