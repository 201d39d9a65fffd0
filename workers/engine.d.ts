// SPDX-License-Identifier: MIT
// Types of the engine facade workers/engine.js.
import type { MachineProfileJson, MeshBuffers, PreviewBuffers, Progress, SettingSpec, Settings } from '../wasm/omnislice';
import { OmnisliceError } from '../wasm/omnislice';

export { OmnisliceError };

export interface CreateSlicerOptions {
  /** URL of slicer-worker.js (default: next to engine.js). */
  workerUrl?: string | URL;
  /** URL of omnislice.mjs (default: /wasm/omnislice.mjs relative to the worker). */
  wasmUrl?: string | URL;
  /** Workers method = auto runs its candidates in (default defaultPoolSize(); 1: one after
   *  another in the slicer's own worker). The delivered program is the same either way. */
  workers?: number;
}

/** Placement keys: scale, fit_mm, up, rotate_x_deg, rotate_y_deg, rotate_z_deg, center. */
export type Placement = Settings;

export type MeshRef = string | { name: string; bytes: ArrayBuffer | ArrayBufferView };

export interface Slicer {
  loadMesh(name: string, arrayBuffer: ArrayBuffer | ArrayBufferView, placement?: Placement):
    Promise<{ meshId: string; info: Record<string, any>; mesh: MeshBuffers }>;
  /** Workers method = auto runs its candidates in. */
  readonly workers: number;
  /** With method = auto, progress events carry `candidate` (a method) besides stage 'auto'. */
  slice(meshIdOrFile: MeshRef, settings?: Settings,
        options?: { onProgress?: (p: Progress & { candidate?: string }) => void; signal?: AbortSignal }):
    Promise<{ program: string; programBytes: Uint8Array; programExtension: 'gcode' | 'csv' | 'script' | 'mod' | 'src';
              report: Record<string, any>; info: Record<string, any>;
              layers: number; preview: PreviewBuffers; mesh: MeshBuffers;
              /** method = auto in a pool of workers: every candidate's result by method (each
               *  made with verify = warn; its report without `auto`). */
              candidates?: Record<string, any> }>;
  info(meshIdOrFile: MeshRef, placement?: Placement, options?: { signal?: AbortSignal }):
    Promise<{ info: Record<string, any>; mesh: MeshBuffers }>;
  verify(program: string, meshIdOrFile: MeshRef,
         options?: { onProgress?: (p: Progress) => void; signal?: AbortSignal; memoryMb?: number }): Promise<Record<string, any>>;
  /** Replay a program through its declared machine (for the machine animation). */
  replay(program: string, options?: { signal?: AbortSignal }):
    Promise<{ profile: MachineProfileJson; format: 'gcode' | 'csv' | 'urscript' | 'rapid' | 'krl'; layers: number; preview: PreviewBuffers }>;
  /** The built-in machine profiles in display order, sized by the settings' bed_size and nozzle. */
  machines(settings?: Settings): Promise<{ name: string; profile: MachineProfileJson; json: string }[]>;
  /** The core's settings table in listing order (defaults, ranges, units, help, choices). */
  settingsSchema(): Promise<SettingSpec[]>;
  /** Check a machine profile JSON with the core's parser; rejects with code 'parse_error'. */
  parseMachine(text: string): Promise<{ profile: MachineProfileJson; json: string }>;
  /** The slicer's own worker's memory and work (helpers of method = auto's pool not counted). */
  stats(): Promise<{ heapBytes: number; usedBytes: number; blocks: number; jobs: number; workersStarted: number }>;
  /** Forget a mesh (its kept bytes here and its copy in the worker). */
  unloadMesh(meshId: string): Promise<void>;
  dispose(): void;
}

/** Cores less one for the page (at 3 or more), within the device's memory at 1 GiB a worker, at most 4. */
export function defaultPoolSize(): number;

export function createSlicer(options?: CreateSlicerOptions): Promise<Slicer>;
