/* e^x and e^x - 1 of one value: lane 0 of the vector forms (as cheap as
   a scalar copy of them on a vector unit, and the same arithmetic). */
F double sexp(double x) { return dexp(dsplat(x))[0]; }
F double sexpm1(double x) { return dexpm1(dsplat(x))[0]; }
F double ssel(double c, double a, double b) { return c != 0.0 ? a : b; }
F double sle(double a, double b) { return a <= b ? 1.0 : 0.0; }
F double seq(double a, double b) { return a == b ? 1.0 : 0.0; }
F double smin(double a, double b) { return a != a ? b : b != b ? a : a < b ? a : b; }
F double smax(double a, double b) { return a != a ? b : b != b ? a : a > b ? a : b; }
F double sabs(double a) { return fabs(a); }
F double slog(double a) { return dlog1(a); }
F double ssin(double a) { return dsin1(a); }
F double scos(double a) { return dcos1(a); }
