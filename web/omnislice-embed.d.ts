// SPDX-License-Identifier: MIT
// Types of the embedding module web/omnislice-embed.js (the package's browser entry "omnislice").
import type { Settings, Progress } from '../wasm/omnislice';
import { OmnisliceError, createSlicer } from '../workers/engine';
import type { Slicer } from '../workers/engine';

export { OmnisliceError, createSlicer };
export type { Slicer };

/** The settings keys that place the mesh (fit_mm, up, rotate_*_deg, scale, center, repair). */
export const PLACEMENT_KEYS: readonly string[];

/** The program's file name for a model file name: ('part.stl', 'csv') -> 'part.csv'. */
export function programFileName(modelName: string, extension?: string): string;

/** The slicer the calls without their own share (started on first use). */
export function sharedSlicer(): Promise<Slicer>;

/** Dispose the shared slicer (its worker ends). */
export function disposeSharedSlicer(): Promise<void>;

export type SliceFileResult = Awaited<ReturnType<Slicer['slice']>> & { fileName: string };

/** The program of a slice result as a Blob. */
export function programBlob(result: SliceFileResult): Blob;

/** Slice one file in a single call: read, load, slice, forget. */
export function sliceFile(
  file: Blob | { name: string; bytes: ArrayBuffer | ArrayBufferView },
  settings?: Settings,
  options?: { onProgress?: (p: Progress) => void; signal?: AbortSignal; slicer?: Slicer; name?: string },
): Promise<SliceFileResult>;
