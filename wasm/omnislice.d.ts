// SPDX-License-Identifier: MIT
// Types of the JS wrapper wasm/omnislice.js (copied next to build/wasm/omnislice.mjs).

export type StatusCode =
  | 'empty_input' | 'unsupported_format' | 'parse_error' | 'truncated_file'
  | 'non_finite_vertex' | 'degenerate_input' | 'open_mesh' | 'non_manifold'
  | 'self_intersecting' | 'invalid_option' | 'io_error' | 'cancelled' | 'unsound_program'
  | 'out_of_memory' | 'internal' | 'worker_failed';

export const STATUS_CODES: readonly ('ok' | StatusCode)[];
export const DEFAULT_MEMORY_MB: number;

export class OmnisliceError extends Error {
  constructor(code: StatusCode | string, message: string);
  readonly name: 'OmnisliceError';
  code: StatusCode;
  /** Set when the wasm instance aborted and must be discarded. */
  fatal?: boolean;
  /** unsound_program (a slice refused after its simulation): the report (with `verify`: the
   *  figures, failures and statement), the input's info, the preview (where it fails) and the
   *  placed mesh, as a slice result would carry them; no program. */
  report?: Record<string, any>;
  info?: Record<string, any>;
  preview?: PreviewBuffers;
  mesh?: MeshBuffers;
}

export type SettingValue = number | string | boolean | number[];
export type Settings = Record<string, SettingValue>;

export interface MeshBuffers {
  positions: Float32Array;   // #V*3, mm, part frame
  indices: Uint32Array;      // #F*3
}

export interface PreviewBuffers {
  positions: Float32Array;   // #S*6: x0 y0 z0 x1 y1 z1 per segment
  features: Uint8Array;      // #S feature code, 0 = travel
  layers: Uint32Array;       // #S layer index
  /** #S*6 machine values at each segment's end: X Y Z (mm) then A or B C (degrees), or q1..q6
   *  (radians) for robot6; unused trailing values 0. Empty when the core wrote none. */
  machine: Float32Array;
  /** #S*3 part-frame nozzle axis (unit) at each segment's end (slice results). */
  axes?: Float32Array;
  /** #S*7 platform pose at each segment's end (part frame -> machine frame; robot6: the robot
   *  base frame): unit quaternion x y z w, then translation x y z (mm), as THREE.Matrix4.compose
   *  takes them. Slice and replay results; empty for an unknown machine kind. */
  poses?: Float32Array;
  /** Curved-layer methods: every layer's regions as one triangle soup, layer per triangle. */
  surfacePositions?: Float32Array;
  surfaceTriangles?: Uint32Array;
  surfaceLayers?: Uint32Array;
  /** Voxel method: centres of missed voxels and support cells (#*3), and the voxel width (mm). */
  missedVoxels?: Float32Array;
  supportVoxels?: Float32Array;
  voxelWidth?: number;
  /** Iso-planar fill (paper 003): #S 1-based NL curve index of each segment in print order,
   *  0 = not on an NL curve (travel, joins, the planar base). Empty for other fills. */
  curves?: Uint32Array;
  /** Geodesic method: segments left out because no nozzle axis clears the part there (the
   *  report's skipped_tool_path warning), #K*6 start and end, part frame, mm, and the layer of
   *  each (#K). */
  skippedSegments?: Float32Array;
  skippedLayers?: Uint32Array;
  /** Multidir method (paper 000): every part's closed mesh as one soup (#V*3, #T*3) with the
   *  part's print index per triangle; risky flags (1 = risky) per triangle of the placed mesh,
   *  along +Z (before) and in the part each face ends up in (after). Empty for other methods. */
  partPositions?: Float32Array;
  partTriangles?: Uint32Array;
  partIds?: Uint32Array;
  riskyBefore?: Uint8Array;
  riskyAfter?: Uint8Array;
  /** The simulated program (report.verify): #*3 part-frame tips of its unsupported and colliding
   *  samples, spread evenly, at most 4000 each; empty with verify = off. */
  unsupportedPoints?: Float32Array;
  collisionPoints?: Float32Array;
}

/** A machine profile as the program header writes it (PROGRAM-FORMAT.md, docs/MACHINES.md). */
export interface MachineProfileJson {
  kind: 'cartesian3' | 'rotary4' | 'table5' | 'head4' | 'head5' | 'robot6' | string;
  pivot?: [number, number, number];
  axis_limits?: Record<string, [number, number]>;
  joint_limits?: [number, number][];
  dh?: [number, number, number, number][];   // robot6: [theta_offset, d, a, alpha], mm / rad
  flange_to_platform?: number[];              // robot6: 16 numbers, row-major
  nozzle_tip?: [number, number, number];      // robot6: robot base frame, mm
  nozzle_axis?: [number, number, number];     // robot6: unit, tip -> hot end
  nozzle?: { diameter: number; cone_half_angle_deg?: number; cone_length?: number };
  [key: string]: any;
}

/** A level of the multidir plane search is done (stage 'decompose'; workers/protocol.js SEARCH_LINES). */
export interface SearchLevel {
  line: 'greedy' | 'constrained' | 'beam' | 'screen' | 'chosen';
  /** Planes in the line's sequences at this level (0 = the uncut model). */
  level: number;
  /** mm²: the least J_G the line reached with at most `level` planes ('chosen': after `level` planes). */
  J_G: number;
  /** Sequences the line goes on extending after this level (0: the line ends). */
  beams: number;
}

export interface Progress { stage: string; fraction: number; search?: SearchLevel }

export interface SliceResult<P = string> {
  program: P;
  report: Record<string, any>;
  info: Record<string, any>;
  layers: number;
  preview: PreviewBuffers;
  /** File extension of the program: 'gcode', 'csv' (robot joint CSV), 'script' (URScript), 'mod' (ABB RAPID) or 'src' (KUKA KRL). */
  programExtension: 'gcode' | 'csv' | 'script' | 'mod' | 'src';
  mesh: MeshBuffers;
}

export function settingsToLines(settings?: Settings): string;

export interface LoadOptions {
  wasmBinary?: ArrayBuffer | Uint8Array;
  locateFile?: (name: string, prefix: string) => string;
  /** URL of omnislice.mjs (default: next to omnislice.js). */
  moduleUrl?: string | URL;
  /** An already imported Emscripten factory. */
  factory?: (args: object) => Promise<any>;
}

export function loadOmnislice(options?: LoadOptions): Promise<Omnislice>;

export class Omnislice {
  readonly raw: any;
  aborted: boolean;
  slice(bytes: ArrayBuffer | Uint8Array, name: string, settings?: Settings,
        options?: { onProgress?: (p: Progress) => boolean | void; programAs?: 'string' }): SliceResult<string>;
  slice(bytes: ArrayBuffer | Uint8Array, name: string, settings: Settings,
        options: { onProgress?: (p: Progress) => boolean | void; programAs: 'bytes' }): SliceResult<Uint8Array>;
  info(bytes: ArrayBuffer | Uint8Array, name: string, placement?: Settings,
       options?: { onProgress?: (p: Progress) => boolean | void }): { info: Record<string, any>; mesh: MeshBuffers };
  /** memoryMb: the memory budget (setting memory_mb's meaning; default DEFAULT_MEMORY_MB). */
  verify(program: string, meshBytes: ArrayBuffer | Uint8Array, meshName: string,
         options?: { onProgress?: (p: Progress) => boolean | void; memoryMb?: number }): Record<string, any>;
  /** method = auto in a pool of workers: the candidates for this mesh and machine. */
  autoPlan(bytes: ArrayBuffer | Uint8Array, name: string, settings?: Settings):
    { candidates: { method: string; settings: Record<string, string> }[]; rerun_settings: Record<string, string> };
  /** method = auto's choice over candidates sliced so far (in the plan's order). */
  autoChoose(settings: Settings, candidates: { method: string; status: string; message?: string; ms?: number;
                                               full?: boolean; report?: Record<string, any> | null }[]):
    { rerun: number } | { chosen: number; status: string; message: string; auto: Record<string, any> };
  /** Replay a program through its declared machine: its profile and moves as preview buffers. */
  replay(program: string): { profile: MachineProfileJson; format: 'gcode' | 'csv' | 'urscript' | 'rapid' | 'krl'; layers: number;
                             preview: PreviewBuffers };
  /** The built-in machine profiles in display order, sized by the settings' bed_size and nozzle. */
  machines(settings?: Settings): { name: string; profile: MachineProfileJson; json: string }[];
  /** Check a machine profile JSON with the core's parser; throws OmnisliceError 'parse_error'. */
  parseMachine(text: string): { profile: MachineProfileJson; json: string };
  /** The settings table in listing order: every key with its type, default, range, unit, help. */
  settingsSchema(): SettingSpec[];
  defaultSettings(): { values: Record<string, string>; keys: string[] };
  /** The instance's memory: linear memory size, bytes malloc holds, free chunks. */
  heapStats(): { heapBytes: number; usedBytes: number; blocks: number };
}

/** One setting of the core's table (core/pipeline/settings.h SettingSpec). */
export interface SettingSpec {
  key: string;
  type: 'number' | 'integer' | 'boolean' | 'choice' | 'vector' | 'text';
  /** The default as text, as program headers write it. */
  default: string;
  /** number, integer: the inclusive range. */
  min?: number;
  max?: number;
  unit: string;
  help: string;
  /** choice, boolean: the accepted values. */
  choices?: string[];
  /** Listed (program header, report) only with this method. */
  method?: string;
}
